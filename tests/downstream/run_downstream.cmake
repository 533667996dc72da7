# ctest's downstream_install (cmake -P): installs the build into a fresh prefix, checks that
# the installed ndtom-map runs from there, then configures, builds and runs three projects
# against the prefix: core/ with OpenCV and MRPT disabled, io_user/ and mrpt_user/.
# -D: BUILD_DIR (the project's build), SOURCE_DIR (this folder), WORK_DIR, GENERATOR, CXX.
cmake_minimum_required(VERSION 3.16)

# Runs a command; stops with its output unless it exits with `expected`.
function(run_expect expected)
  execute_process(COMMAND ${ARGN} RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE out)
  string(REPLACE ";" " " command "${ARGN}")
  if(NOT "${rc}" STREQUAL "${expected}")
    message(FATAL_ERROR "exit status ${rc} (expected ${expected}): ${command}\n${out}")
  endif()
  message(STATUS "ok (exit ${rc}): ${command}\n${out}")
endfunction()

set(prefix ${WORK_DIR}/prefix)
file(REMOVE_RECURSE ${WORK_DIR})
run_expect(0 ${CMAKE_COMMAND} --install ${BUILD_DIR} --prefix ${prefix})

foreach(file bin/ndtom-map bin/ndtom-slam share/ndtom/mrpt/observations2map_ndtom.ini
        share/ndtom/mrpt/ndtom-slam.ini
        share/ndtom/data/tum-fr2-pioneer-slam2/associations.txt)
  if(NOT EXISTS ${prefix}/${file})
    message(FATAL_ERROR "not installed: ${file}")
  endif()
endforeach()
# RPATH $ORIGIN/../lib: runs from the prefix without LD_LIBRARY_PATH.
run_expect(0 ${prefix}/bin/ndtom-map --help)
run_expect(0 ${prefix}/bin/ndtom-slam --help)

set(configure_args -G ${GENERATOR} -DCMAKE_BUILD_TYPE=Release -DCMAKE_CXX_COMPILER=${CXX}
    -DCMAKE_PREFIX_PATH=${prefix})

# (a) The core alone: the package must not need OpenCV or MRPT to configure.
run_expect(0 ${CMAKE_COMMAND} -S ${SOURCE_DIR}/core -B ${WORK_DIR}/core ${configure_args}
  -DCMAKE_DISABLE_FIND_PACKAGE_OpenCV=ON -DCMAKE_DISABLE_FIND_PACKAGE_mrpt-maps=ON
  -DCMAKE_DISABLE_FIND_PACKAGE_mrpt-opengl=ON -DCMAKE_DISABLE_FIND_PACKAGE_mrpt-slam=ON)
run_expect(0 ${CMAKE_COMMAND} --build ${WORK_DIR}/core -j2)
run_expect(0 ${WORK_DIR}/core/core_user)

# The readers, on the installed demo frames.
run_expect(0 ${CMAKE_COMMAND} -S ${SOURCE_DIR}/io_user -B ${WORK_DIR}/io_user ${configure_args})
run_expect(0 ${CMAKE_COMMAND} --build ${WORK_DIR}/io_user -j2)
run_expect(0 ${WORK_DIR}/io_user/io_user ${prefix}/share/ndtom/data/tum-fr2-pioneer-slam2)

# (b) The map from .ini text under --as-needed; the bare link is the control that loses it.
run_expect(0 ${CMAKE_COMMAND} -S ${SOURCE_DIR}/mrpt_user -B ${WORK_DIR}/mrpt_user ${configure_args})
run_expect(0 ${CMAKE_COMMAND} --build ${WORK_DIR}/mrpt_user -j2)
run_expect(0 ${WORK_DIR}/mrpt_user/ini_user)
run_expect(0 ${WORK_DIR}/mrpt_user/ini_user_call)
run_expect(3 ${WORK_DIR}/mrpt_user/ini_user_bare)
run_expect(0 ${WORK_DIR}/mrpt_user/builder_user ${prefix}/share/ndtom/mrpt/ndtom-slam.ini)

# (c) The Debian package (cpack -G DEB, as doc/mrpt.md says): it builds, declares MRPT's
# runtime libraries, and its programs run from the extracted files with no install.
find_program(DPKG_DEB dpkg-deb)
if(DPKG_DEB)
  run_expect(0 ${CMAKE_COMMAND} -E chdir ${BUILD_DIR} cpack -G DEB -B ${WORK_DIR}/deb)
  file(GLOB debs ${WORK_DIR}/deb/ndtom_*.deb)
  list(LENGTH debs count)
  if(NOT count EQUAL 1)
    message(FATAL_ERROR "cpack made ${count} .deb files in ${WORK_DIR}/deb")
  endif()
  execute_process(COMMAND ${DPKG_DEB} -f ${debs} Depends OUTPUT_VARIABLE depends)
  if(NOT depends MATCHES "libmrpt-maps")
    message(FATAL_ERROR "the .deb does not depend on MRPT's maps library: ${depends}")
  endif()
  run_expect(0 ${DPKG_DEB} -x ${debs} ${WORK_DIR}/deb/root)
  run_expect(0 ${WORK_DIR}/deb/root/usr/bin/ndtom-map --help)
  if(NOT EXISTS ${WORK_DIR}/deb/root/usr/lib/cmake/ndtom/ndtomConfig.cmake AND
     NOT EXISTS ${WORK_DIR}/deb/root/usr/lib/x86_64-linux-gnu/cmake/ndtom/ndtomConfig.cmake)
    message(FATAL_ERROR "the .deb has no CMake package")
  endif()
endif()
