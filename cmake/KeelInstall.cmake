# Install rules: `cmake --install build --prefix P` gives a relocatable tree
#   P/bin/keel                    the CLI; RPATH $ORIGIN/../lib finds libkeel
#   P/lib/libkeel.so*             the framework (with its soname links)
#   P/lib/libkeel_opros.so*       keel's OPRoS layer, linked by OPRoS component sources
#   P/lib/keel/*.so               keel's stock component libraries (found next to libkeel), the
#                                 test robot's among them
#   P/bin/keel-host               a component process of keel run (found next to bin/keel)
#   P/bin/keel_motion_board       the robot's board program (robot/CMakeLists.txt)
#   P/share/keel/profiles/        the stock components' profiles (components/CMakeLists.txt)
#   P/share/keel/robot/           the robot's profiles and scenarios (robot/CMakeLists.txt)
#   P/include/keel/**             the public headers, the shipped messages' generated ones among
#                                 them (include/keel/msg/<pkg>/msg/, msgs/CMakeLists.txt)
#   P/include/keel/idlc/          idlc's C headers of the shipped messages (<pkg>/msg/<Name>_.h)
#   P/share/keel/msgs/            the shipped .msg and .srv files, their LICENSE and SOURCES.md
#   P/share/keel/idl/             the shipped messages' IDL, which a user's IDL includes
#   P/lib/cmake/keel/             the CMake package: find_package(keel CONFIG) gives keel::keel,
#                                 keel::opros, keel::cli, keel::msgs_headers, keel_add_component(),
#                                 keel_add_opros_component() and keel_add_messages() (with
#                                 keel_msggen.py, its generator)
# "lib" above is ${CMAKE_INSTALL_LIBDIR}. Included at the end of the root CMakeLists, after every
# target is defined. No absolute path of the build or source tree ends up in the install.
include_guard(GLOBAL)
include(GNUInstallDirs)
include(CMakePackageConfigHelpers)

set(KEEL_INSTALL_CMAKEDIR "${CMAKE_INSTALL_LIBDIR}/cmake/keel"
    CACHE STRING "Where to install keel's CMake package, relative to the prefix")
set(KEEL_INSTALL_COMPONENTDIR "${CMAKE_INSTALL_LIBDIR}/keel")
set(KEEL_INSTALL_MSGDIR "${CMAKE_INSTALL_DATADIR}/keel/msgs")
set(KEEL_INSTALL_IDLDIR "${CMAKE_INSTALL_DATADIR}/keel/idl")

# RPATHs relative to the installed file, so the prefix can be moved. CMake replaces the build
# RPATH with these when it installs.
file(RELATIVE_PATH _keel_bin_to_lib "/${CMAKE_INSTALL_BINDIR}" "/${CMAKE_INSTALL_LIBDIR}")
set_target_properties(keel PROPERTIES INSTALL_RPATH "$ORIGIN")
set_target_properties(keel_cli PROPERTIES INSTALL_RPATH "$ORIGIN/${_keel_bin_to_lib}"
                                          EXPORT_NAME cli)
set_target_properties(keel_host PROPERTIES INSTALL_RPATH "$ORIGIN/${_keel_bin_to_lib}" EXPORT_NAME host)
set_target_properties(keel_node_exec PROPERTIES EXPORT_NAME node_exec)

set_target_properties(keel_opros PROPERTIES INSTALL_RPATH "$ORIGIN")

install(TARGETS keel keel_opros keel_cli keel_host keel_node_exec
  EXPORT keelTargets
  RUNTIME DESTINATION "${CMAKE_INSTALL_BINDIR}" COMPONENT keel_runtime
  LIBRARY DESTINATION "${CMAKE_INSTALL_LIBDIR}" COMPONENT keel_runtime
          NAMELINK_COMPONENT keel_development)

install(DIRECTORY "${PROJECT_SOURCE_DIR}/include/keel"
  DESTINATION "${CMAKE_INSTALL_INCLUDEDIR}" COMPONENT keel_development
  FILES_MATCHING PATTERN "*.hpp" PATTERN "*.h" PATTERN "*.inl")

# The shipped messages (msgs/): generated C++ headers, idlc's C headers, IDL and .msg files, and
# keel::msgs_headers, the include directories a user's keel_add_messages target needs.
install(TARGETS keel_msgs_headers EXPORT keelTargets)
install(DIRECTORY "${PROJECT_BINARY_DIR}/msgs/include/keel"
  DESTINATION "${CMAKE_INSTALL_INCLUDEDIR}" COMPONENT keel_development FILES_MATCHING PATTERN "*.hpp")
install(DIRECTORY "${PROJECT_BINARY_DIR}/msgs/idlc/"
  DESTINATION "${CMAKE_INSTALL_INCLUDEDIR}/keel/idlc" COMPONENT keel_development FILES_MATCHING PATTERN "*.h")
install(DIRECTORY "${PROJECT_BINARY_DIR}/msgs/idl/"
  DESTINATION "${KEEL_INSTALL_IDLDIR}" COMPONENT keel_development FILES_MATCHING PATTERN "*.idl")
install(DIRECTORY "${PROJECT_SOURCE_DIR}/msgs/"
  DESTINATION "${KEEL_INSTALL_MSGDIR}" COMPONENT keel_development
  FILES_MATCHING PATTERN "*.msg" PATTERN "*.srv" PATTERN "LICENSE" PATTERN "SOURCES.md")

# keel's own component libraries (keel_add_component outside tests/examples; see
# cmake/KeelComponent.cmake). libkeel looks for them in <dir of libkeel.so>/keel.
get_property(_keel_stock GLOBAL PROPERTY KEEL_STOCK_COMPONENTS)
if(_keel_stock)
  set_target_properties(${_keel_stock} PROPERTIES INSTALL_RPATH "$ORIGIN/..")
  install(TARGETS ${_keel_stock}
    LIBRARY DESTINATION "${KEEL_INSTALL_COMPONENTDIR}" COMPONENT keel_runtime)
endif()

# The CMake package.
install(EXPORT keelTargets
  NAMESPACE keel::
  DESTINATION "${KEEL_INSTALL_CMAKEDIR}" COMPONENT keel_development)
configure_package_config_file(
  "${PROJECT_SOURCE_DIR}/cmake/keelConfig.cmake.in"
  "${PROJECT_BINARY_DIR}/cmake/keelConfig.cmake"
  INSTALL_DESTINATION "${KEEL_INSTALL_CMAKEDIR}"
  PATH_VARS CMAKE_INSTALL_INCLUDEDIR KEEL_INSTALL_COMPONENTDIR CMAKE_INSTALL_BINDIR KEEL_INSTALL_MSGDIR
            KEEL_INSTALL_IDLDIR)
# 0.x: a minor version may break the API, so only the same minor version is compatible.
write_basic_package_version_file(
  "${PROJECT_BINARY_DIR}/cmake/keelConfigVersion.cmake"
  VERSION "${PROJECT_VERSION}"
  COMPATIBILITY SameMinorVersion)
install(FILES
  "${PROJECT_BINARY_DIR}/cmake/keelConfig.cmake"
  "${PROJECT_BINARY_DIR}/cmake/keelConfigVersion.cmake"
  "${PROJECT_SOURCE_DIR}/cmake/KeelComponent.cmake"
  "${PROJECT_SOURCE_DIR}/cmake/KeelMessages.cmake"
  "${PROJECT_SOURCE_DIR}/cmake/keel_msggen.py"
  DESTINATION "${KEEL_INSTALL_CMAKEDIR}" COMPONENT keel_development)

unset(_keel_stock)
unset(_keel_bin_to_lib)
