# keel_add_component(<target> SOURCES <src>...
#                    [OUTPUT_DIRECTORY <dir>]
#                    [INSTALL [DESTINATION <dir>]] [NO_INSTALL])
#
# Builds a loadable component library: a MODULE library `lib<target>.so` linked to keel::keel.
# One library may hold several components, each registered with KEEL_REGISTER_COMPONENT; a
# component profile names the library in `execution_environment/library_name`.
#
# Used by component authors through `find_package(keel CONFIG REQUIRED)` and by keel's own tree.
#   OUTPUT_DIRECTORY  where the library is built. Default: the author's usual library output
#                     (CMAKE_LIBRARY_OUTPUT_DIRECTORY, else the current binary dir); in keel's
#                     own tree, build/lib/keel, where build/bin/keel finds it.
#   INSTALL           also install the library, by default into `<prefix>/lib/keel`
#                     (`${CMAKE_INSTALL_LIBDIR}/keel`): installed into keel's own prefix, the
#                     `keel` command then finds it with no KEEL_COMPONENT_PATH.
#   DESTINATION       install directory instead of `${CMAKE_INSTALL_LIBDIR}/keel`.
#   NO_INSTALL        keel's tree only: not a stock component (a test or example fixture).
#
# In keel's own tree every component is a stock component, installed with keel, except those
# defined under tests/, examples/, bench/ or fuzz/ and those marked NO_INSTALL. Stock targets are
# listed in the global property KEEL_STOCK_COMPONENTS, which cmake/KeelInstall.cmake installs.
include_guard(GLOBAL)

function(keel_add_component target)
  cmake_parse_arguments(PARSE_ARGV 1 ARG "INSTALL;NO_INSTALL" "OUTPUT_DIRECTORY;DESTINATION"
                        "SOURCES")
  if(ARG_UNPARSED_ARGUMENTS)
    message(FATAL_ERROR "keel_add_component(${target}): unknown arguments: "
                        "${ARG_UNPARSED_ARGUMENTS} (expected SOURCES, OUTPUT_DIRECTORY, "
                        "INSTALL, DESTINATION, NO_INSTALL)")
  endif()
  if(NOT ARG_SOURCES)
    message(FATAL_ERROR "keel_add_component(${target}): SOURCES is required")
  endif()
  if(ARG_INSTALL AND ARG_NO_INSTALL)
    message(FATAL_ERROR "keel_add_component(${target}): INSTALL and NO_INSTALL exclude each other")
  endif()
  if(ARG_DESTINATION AND NOT ARG_INSTALL)
    message(FATAL_ERROR "keel_add_component(${target}): DESTINATION needs INSTALL")
  endif()
  if(NOT TARGET keel::keel)
    message(FATAL_ERROR "keel_add_component(${target}): target keel::keel is not defined; "
                        "call find_package(keel CONFIG REQUIRED) first")
  endif()

  add_library(${target} MODULE ${ARG_SOURCES})
  target_link_libraries(${target} PRIVATE keel::keel)
  target_compile_features(${target} PRIVATE cxx_std_20)
  # The runtime looks a profile's library_name up as lib<name>.so. Default visibility: an
  # author's classes behave as in any shared library (RTTI, exceptions across libkeel).
  set_target_properties(${target} PROPERTIES PREFIX "lib" SUFFIX ".so"
                                             CXX_VISIBILITY_PRESET default)

  if(ARG_OUTPUT_DIRECTORY)
    set_target_properties(${target} PROPERTIES LIBRARY_OUTPUT_DIRECTORY "${ARG_OUTPUT_DIRECTORY}")
  elseif(KEEL_IN_TREE AND DEFINED KEEL_COMPONENT_OUTPUT_DIRECTORY)
    set_target_properties(${target} PROPERTIES
                          LIBRARY_OUTPUT_DIRECTORY "${KEEL_COMPONENT_OUTPUT_DIRECTORY}")
  endif()

  if(KEEL_IN_TREE)
    _keel_is_stock_component(stock "${ARG_INSTALL}" "${ARG_NO_INSTALL}")
    if(stock)
      set_property(GLOBAL APPEND PROPERTY KEEL_STOCK_COMPONENTS ${target})
    endif()
  elseif(ARG_INSTALL)
    if(ARG_DESTINATION)
      set(destination "${ARG_DESTINATION}")
    elseif(DEFINED CMAKE_INSTALL_LIBDIR)
      set(destination "${CMAKE_INSTALL_LIBDIR}/keel")
    else()
      set(destination "lib/keel")
    endif()
    # libkeel is already loaded when the runtime dlopens a component; the RPATH only helps
    # tools (ldd) when the component sits in keel's own prefix.
    set_target_properties(${target} PROPERTIES INSTALL_RPATH "$ORIGIN/..")
    install(TARGETS ${target} LIBRARY DESTINATION "${destination}")
  endif()
endfunction()

# Stock unless NO_INSTALL, or defined under tests/, examples/, bench/ or fuzz/ of keel's tree
# without an explicit INSTALL.
function(_keel_is_stock_component out install no_install)
  set(stock TRUE)
  if(no_install)
    set(stock FALSE)
  elseif(NOT install)
    file(RELATIVE_PATH rel "${keel_SOURCE_DIR}" "${CMAKE_CURRENT_SOURCE_DIR}")
    if(rel MATCHES "^(tests|examples|bench|fuzz)(/|$)")
      set(stock FALSE)
    endif()
  endif()
  set(${out} ${stock} PARENT_SCOPE)
endfunction()

# keel_add_opros_component(<target> SOURCES <src>...
#                          [OUTPUT_DIRECTORY <dir>] [INSTALL [DESTINATION <dir>]] [NO_INSTALL])
#
# Builds a component written for OPRoS, from its sources unchanged, into a loadable library
# `lib<target>.so` (docs/opros.md). The sources see keel's OPRoS headers by the names they
# include (<Component.h>, <OPRoSInclude.h>, "device/ApiTypes.h", "ApiTypes.h"), with
# MAKE_COMPONENT_DLL and _OPROS_LINUX_ defined as OPRoS's build files had them, and the library
# links keel::opros, through which keel hosts the object its getComponent() makes. Name the
# library in the component profile's library_name as for OPRoS ("<target>", "lib<target>.so"
# or OPRoS's "<target>.dll"). The options are keel_add_component's. keel's warnings flags are
# not added: such sources were written for compilers of their day.
function(keel_add_opros_component target)
  cmake_parse_arguments(PARSE_ARGV 1 ARG "INSTALL;NO_INSTALL" "OUTPUT_DIRECTORY;DESTINATION" "SOURCES")
  if(ARG_UNPARSED_ARGUMENTS)
    message(FATAL_ERROR "keel_add_opros_component(${target}): unknown arguments: "
                        "${ARG_UNPARSED_ARGUMENTS} (expected SOURCES, OUTPUT_DIRECTORY, "
                        "INSTALL, DESTINATION, NO_INSTALL)")
  endif()
  if(NOT TARGET keel::opros)
    message(FATAL_ERROR "keel_add_opros_component(${target}): target keel::opros is not defined; "
                        "call find_package(keel CONFIG REQUIRED) first")
  endif()
  set(forward SOURCES ${ARG_SOURCES})
  foreach(flag INSTALL NO_INSTALL)
    if(ARG_${flag})
      list(APPEND forward ${flag})
    endif()
  endforeach()
  foreach(value OUTPUT_DIRECTORY DESTINATION)
    if(ARG_${value})
      list(APPEND forward ${value} "${ARG_${value}}")
    endif()
  endforeach()
  keel_add_component(${target} ${forward})
  target_link_libraries(${target} PRIVATE keel::opros)
  target_compile_definitions(${target} PRIVATE MAKE_COMPONENT_DLL _OPROS_LINUX_)
endfunction()
