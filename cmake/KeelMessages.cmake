# keel_add_messages(<target> FILES <file.msg|file.srv>... [PACKAGE <pkg>] [SHARED]
#                   [OUTPUT_DIRECTORY <dir>])
#
# Builds C++ types for ROS 2 messages (.msg files) and services (.srv files) and their DDS
# conversions into the library <target> (docs/messages.md). A service pkg/srv/Name is two
# messages, pkg/srv/Name_Request and pkg/srv/Name_Response (keel::msg::<pkg>::Name_Request, ...,
# under <keel/msg/<pkg>/srv/>, and <keel/msg/<pkg>/srv/<name>.hpp> with both), as DDS carries a
# ROS 2 service. For each message pkg/Name, at build time:
#   keel_msggen.py (next to this file) writes the IDL, the C++ header
#     <keel/msg/<pkg>/msg/<name>.hpp> (keel::msg::<pkg>::<Name>), its conversions to the C sample
#     (<keel/msg/<pkg>/msg/detail/<name>__dds.hpp>), the table of its fields by name
#     (<keel/msg/<pkg>/msg/detail/<name>__fields.hpp>) and a .cpp that registers the type with
#     keel's DDS layer under "<pkg>/msg/<Name>";
#   CycloneDDS's idlc -t -x final turns the IDL into the C sample type and its descriptor.
# Editing a .msg file regenerates its code on the next build.
#
#   FILES             the .msg and .srv files. Each file's package is the name of the directory
#                     above its `msg/` (`srv/`) directory (.../my_msgs/msg/Foo.msg: my_msgs), as
#                     in a ROS 2 package.
#   PACKAGE           the package of every file instead (for files not laid out that way).
#   SHARED            a shared library instead of an OBJECT library (below).
#   OUTPUT_DIRECTORY  where the generated files go; default ${CMAKE_CURRENT_BINARY_DIR}/<target>.
#
# <target> is an OBJECT library by default: link it into the component library that uses the
# types (keel_add_component's MODULE), and its objects become part of that library, with nothing
# more to install or find at run time. When several component libraries of one process use the
# same messages, SHARED builds one lib<target>.so they all link (one registration, one copy of
# the code); that library must then be found at run time as any other (RPATH, install).
# Either way <target> gives its users the generated include directories and links keel::keel,
# keel's shipped message headers and CycloneDDS::ddsc. Fields may use keel's shipped messages
# (std_msgs/Header, geometry_msgs/Twist, ...); a message keel ships cannot be defined again.
#
# Needs Python 3, CycloneDDS 0.10's CMake package and idlc (Debian: cyclonedds-dev,
# cyclonedds-tools). idlc is run directly, not through CycloneDDS's idlc_generate(): that one
# makes an INTERFACE library whose idlc .c files are compiled into every target linking it (two
# copies of each descriptor when a message library reaches a program twice, as keel_msgs does
# through libkeel), needs the C language enabled, writes into CMAKE_CURRENT_BINARY_DIR only and
# leaves the build tree's path in the headers. Here idlc's C source is compiled as C++ inside the
# registering .cpp, so a project needs no C compiler. A SHARED <target> is linked --no-as-needed
# by its users: they reference none of its symbols (the types are in headers) but need its
# registrations.
#
# Used by authors through find_package(keel CONFIG REQUIRED) (keelConfig.cmake sets
# KEEL_MSG_DIR and KEEL_MSG_IDL_DIR, the shipped .msg and IDL) and by keel's own tree, where
# msgs/CMakeLists.txt builds the shipped messages as keel_msgs.
include_guard(GLOBAL)

set(_KEEL_MSGGEN "${CMAKE_CURRENT_LIST_DIR}/keel_msggen.py")
if(KEEL_IN_TREE)
  set(KEEL_MSG_DIR "${PROJECT_SOURCE_DIR}/msgs")
  set(KEEL_MSG_IDL_DIR "${PROJECT_BINARY_DIR}/msgs/idl")
endif()

function(keel_add_messages target)
  cmake_parse_arguments(PARSE_ARGV 1 ARG "SHARED" "PACKAGE;OUTPUT_DIRECTORY" "FILES")
  if(ARG_UNPARSED_ARGUMENTS)
    message(FATAL_ERROR "keel_add_messages(${target}): unknown arguments: ${ARG_UNPARSED_ARGUMENTS} "
                        "(expected FILES, PACKAGE, SHARED, OUTPUT_DIRECTORY)")
  endif()
  if(NOT ARG_FILES)
    message(FATAL_ERROR "keel_add_messages(${target}): FILES is required")
  endif()
  # keel's own shipped set (msgs/CMakeLists.txt): it goes into libkeel, so it cannot link it.
  set(shipped "${_KEEL_SHIPPED_MESSAGES}")
  if(NOT shipped AND NOT KEEL_IN_TREE AND NOT TARGET keel::keel)
    message(FATAL_ERROR "keel_add_messages(${target}): target keel::keel is not defined; "
                        "call find_package(keel CONFIG REQUIRED) first")
  endif()
  _keel_message_tools(${target})

  if(ARG_OUTPUT_DIRECTORY)
    set(out "${ARG_OUTPUT_DIRECTORY}")
  else()
    set(out "${CMAKE_CURRENT_BINARY_DIR}/${target}")
  endif()

  # The files: package, name and interface (msg or srv) of each, and the set of messages (for
  # the generator's checks).
  set(messages)
  set(known)
  set(files)
  foreach(file IN LISTS ARG_FILES)
    get_filename_component(path "${file}" ABSOLUTE)
    get_filename_component(name "${path}" NAME_WLE)
    get_filename_component(ext "${path}" LAST_EXT)
    if(NOT ext STREQUAL ".msg" AND NOT ext STREQUAL ".srv")
      message(FATAL_ERROR "keel_add_messages(${target}): ${file} is not a .msg or .srv file "
                          "(actions are not supported)")
    endif()
    string(SUBSTRING "${ext}" 1 -1 iface)
    if(NOT EXISTS "${path}")
      message(FATAL_ERROR "keel_add_messages(${target}): ${path} does not exist")
    endif()
    if(ARG_PACKAGE)
      set(pkg "${ARG_PACKAGE}")
    else()
      get_filename_component(dir "${path}" DIRECTORY)
      get_filename_component(dir_name "${dir}" NAME)
      get_filename_component(pkg_dir "${dir}" DIRECTORY)
      get_filename_component(pkg "${pkg_dir}" NAME)
      if(NOT dir_name STREQUAL iface OR pkg STREQUAL "")
        message(FATAL_ERROR "keel_add_messages(${target}): ${file} is not in a <package>/${iface}/ "
                            "directory: give its package with PACKAGE <name>")
      endif()
    endif()
    if("${pkg}/${iface}/${name}" IN_LIST files)
      message(FATAL_ERROR "keel_add_messages(${target}): ${pkg}/${iface}/${name} is given twice")
    endif()
    list(APPEND files "${pkg}/${iface}/${name}")
    if(iface STREQUAL "msg")
      list(APPEND known "${pkg}/${name}")
    endif()
    list(APPEND messages "${pkg}|${name}|${path}|${iface}")
  endforeach()

  set(gen_args --out "${out}")
  set(idlc_includes -I idl)
  if(NOT shipped)
    list(APPEND gen_args --search "${KEEL_MSG_DIR}")
    list(APPEND idlc_includes -I "${KEEL_MSG_IDL_DIR}")
  endif()
  foreach(k IN LISTS known)
    list(APPEND gen_args --known "${k}")
  endforeach()

  set(idls)
  set(generated)
  set(sources)
  set(types)  # "pkg|iface|Name" of each message type, a service's two halves each
  foreach(m IN LISTS messages)
    string(REPLACE "|" ";" m "${m}")
    list(GET m 0 pkg)
    list(GET m 1 name)
    list(GET m 2 path)
    list(GET m 3 iface)
    set(include "${out}/include/keel/msg/${pkg}/${iface}")
    _keel_snake_case(snake "${name}")
    set(outputs)
    if(iface STREQUAL "srv")
      set(halves "${name}_Request|${snake}_request" "${name}_Response|${snake}_response")
      list(APPEND outputs "${include}/${snake}.hpp")
    else()
      set(halves "${name}|${snake}")
    endif()
    foreach(half IN LISTS halves)
      string(REPLACE "|" ";" half "${half}")
      list(GET half 0 type)
      list(GET half 1 type_snake)
      list(APPEND outputs "${out}/idl/${pkg}/${iface}/${type}_.idl" "${include}/${type_snake}.hpp"
                          "${include}/detail/${type_snake}__dds.hpp" "${include}/detail/${type_snake}__fields.hpp")
      list(APPEND idls "${out}/idl/${pkg}/${iface}/${type}_.idl")
      list(APPEND outputs "${out}/src/${pkg}/${iface}/${type_snake}__dds.cpp")
      list(APPEND sources "${out}/src/${pkg}/${iface}/${type_snake}__dds.cpp")
      list(APPEND types "${pkg}|${iface}|${type}")
    endforeach()
    add_custom_command(
      OUTPUT ${outputs}
      COMMAND "${Python3_EXECUTABLE}" "${_KEEL_MSGGEN}" ${gen_args} --package "${pkg}" "${path}"
      DEPENDS "${path}" "${_KEEL_MSGGEN}"
      COMMENT "keel_msggen ${pkg}/${iface}/${name}"
      VERBATIM)
    list(APPEND generated ${outputs})
  endforeach()

  # idlc, run in ${out} on relative paths, so that its output names no absolute path (the header
  # guards come from the output path; the IDL's path in the header comment is made relative
  # after). Each C file also holds the ops of the types it nests, so it is remade when any IDL of
  # the set changes.
  foreach(t IN LISTS types)
    string(REPLACE "|" ";" t "${t}")
    list(GET t 0 pkg)
    list(GET t 1 iface)
    list(GET t 2 type)
    set(c_out "${out}/idlc/${pkg}/${iface}/${type}_")
    add_custom_command(
      OUTPUT "${c_out}.c" "${c_out}.h"
      COMMAND "${KEEL_IDLC_EXECUTABLE}" -t -x final ${idlc_includes} -b idl -o idlc
              "idl/${pkg}/${iface}/${type}_.idl"
      COMMAND "${Python3_EXECUTABLE}" "${_KEEL_MSGGEN}" --idlc-output "${c_out}.c" "${c_out}.h"
      WORKING_DIRECTORY "${out}"
      DEPENDS ${idls} "${KEEL_IDLC_EXECUTABLE}" "${_KEEL_MSGGEN}"
      COMMENT "idlc ${pkg}/${iface}/${type}_.idl"
      VERBATIM)
    list(APPEND generated "${c_out}.c" "${c_out}.h")
  endforeach()

  add_custom_target(${target}_generate DEPENDS ${generated} ${sources})
  if(shipped)
    add_library(${target} OBJECT ${sources})
  elseif(ARG_SHARED)
    add_library(${target} SHARED ${sources})
    # Its users reference nothing of it (the types are in headers) but need it loaded for its
    # registrations: a linker with --as-needed (Debian's and Ubuntu's default) would drop it.
    target_link_options(${target} INTERFACE "LINKER:--no-as-needed")
  else()
    add_library(${target} OBJECT ${sources})
  endif()
  add_dependencies(${target} ${target}_generate)
  set_target_properties(${target} PROPERTIES POSITION_INDEPENDENT_CODE ON)
  target_compile_features(${target} PUBLIC cxx_std_20)
  target_include_directories(${target} PUBLIC "$<BUILD_INTERFACE:${out}/include>"
                                              "$<BUILD_INTERFACE:${out}/idlc>")
  if(shipped)
    target_link_libraries(${target} PUBLIC keel_msgs_headers)
  else()
    target_link_libraries(${target} PUBLIC keel::keel keel::msgs_headers CycloneDDS::ddsc)
    if(TARGET keel_msgs_generate)  # keel's tree: the shipped messages' headers come first
      add_dependencies(${target}_generate keel_msgs_generate)
    endif()
  endif()
endfunction()

# Python, idlc and CycloneDDS, found once per directory; errors name what to install.
macro(_keel_message_tools target)
  if(NOT Python3_EXECUTABLE)
    find_package(Python3 3.8 COMPONENTS Interpreter QUIET)
    if(NOT Python3_FOUND)
      message(FATAL_ERROR "keel_add_messages(${target}): Python 3 not found (keel_msggen.py needs it)")
    endif()
  endif()
  if(NOT TARGET CycloneDDS::ddsc)
    find_package(CycloneDDS 0.10 QUIET)
    if(NOT CycloneDDS_FOUND)
      message(FATAL_ERROR "keel_add_messages(${target}): CycloneDDS 0.10's CMake package not found "
                          "(Debian: apt-get install cyclonedds-dev)")
    endif()
  endif()
  find_program(KEEL_IDLC_EXECUTABLE idlc DOC "CycloneDDS's IDL compiler, for keel_add_messages")
  if(NOT KEEL_IDLC_EXECUTABLE)
    message(FATAL_ERROR "keel_add_messages(${target}): CycloneDDS's idlc not found "
                        "(Debian: apt-get install cyclonedds-tools)")
  endif()
endmacro()

# <out> = rosidl's snake case of a message name (PoseStamped: pose_stamped, the file name of its
# header), as keel_msggen.py's snake_case().
function(_keel_snake_case out name)
  string(REGEX REPLACE "(.)([A-Z][a-z]+)" "\\1_\\2" s "${name}")
  string(REGEX REPLACE "([a-z0-9])([A-Z])" "\\1_\\2" s "${s}")
  string(TOLOWER "${s}" s)
  set(${out} "${s}" PARENT_SCOPE)
endfunction()
