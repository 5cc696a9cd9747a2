# The robot's profiles (the application, its apps, component profiles and fault scenarios) as
# they are installed, in <prefix>/share/keel/robot with their layout. In the source tree they
# reference keel's stock component profiles as ../components/<area>/X.xml; installed, those are
# in <prefix>/share/keel/profiles, so each such reference becomes ../profiles/X.xml (the same
# number of ../, as robot/ and profiles/ are siblings under share/keel).
#
# keel_robot_installed_profiles(<source dir> <output dir>): writes the rewritten copies at
# configure time (CMake configures again when a source profile changes); robot/CMakeLists.txt
# installs the output directory.
function(keel_robot_installed_profiles source output)
  file(GLOB_RECURSE profiles RELATIVE "${source}" CONFIGURE_DEPENDS "${source}/*.xml")
  file(REMOVE_RECURSE "${output}")
  foreach(rel IN LISTS profiles)
    set_property(DIRECTORY APPEND PROPERTY CMAKE_CONFIGURE_DEPENDS "${source}/${rel}")
    file(READ "${source}/${rel}" text)
    string(REGEX REPLACE "((\\.\\./)+)components/(monitors|voters|estimators)/" "\\1profiles/" text "${text}")
    file(WRITE "${output}/${rel}" "${text}")
  endforeach()
endfunction()
