# Installs the libraries, headers, programs and shared data under GNUInstallDirs paths, and
# the CMake package `ndtom` (find_package(ndtom CONFIG)). Each library has its own export set
# so that the core's targets file needs only Eigen: ndtom_io's loads OpenCV, mrpt_ndtom's MRPT.
include(CMakePackageConfigHelpers)
set(NDTOM_CMAKE_DIR ${CMAKE_INSTALL_LIBDIR}/cmake/ndtom)

# A library of libs/NAME: its targets, its include/ folder and its export set NAME-targets.
function(ndtom_install_library name)
  install(TARGETS ${ARGN} EXPORT ${name}-targets)
  install(DIRECTORY ${PROJECT_SOURCE_DIR}/libs/${name}/include/
          DESTINATION ${CMAKE_INSTALL_INCLUDEDIR})
  install(EXPORT ${name}-targets NAMESPACE ndtom:: DESTINATION ${NDTOM_CMAKE_DIR})
endfunction()

ndtom_install_library(ndtom ndtom)

set(NDTOM_EXPORTED_COMPONENTS "")
# The evaluation's measures: installed so that users can score their own maps as the paper
# does (ndtom-eval and ndtom-bench link it statically). Eigen only, as the core.
if(TARGET ndtom_eval)
  ndtom_install_library(ndtom_eval ndtom_eval)
  list(APPEND NDTOM_EXPORTED_COMPONENTS ndtom_eval)
endif()
if(TARGET ndtom_io)
  ndtom_install_library(ndtom_io ndtom_io)
  list(APPEND NDTOM_EXPORTED_COMPONENTS ndtom_io)
endif()
if(TARGET mrpt_ndtom)
  ndtom_install_library(mrpt_ndtom mrpt_ndtom mrpt_ndtom_linked)
  list(APPEND NDTOM_EXPORTED_COMPONENTS mrpt_ndtom)
endif()

configure_package_config_file(${CMAKE_CURRENT_LIST_DIR}/ndtomConfig.cmake.in
  ${PROJECT_BINARY_DIR}/ndtomConfig.cmake INSTALL_DESTINATION ${NDTOM_CMAKE_DIR})
write_basic_package_version_file(${PROJECT_BINARY_DIR}/ndtomConfigVersion.cmake
  COMPATIBILITY SameMajorVersion)
install(FILES ${PROJECT_BINARY_DIR}/ndtomConfig.cmake ${PROJECT_BINARY_DIR}/ndtomConfigVersion.cmake
        DESTINATION ${NDTOM_CMAKE_DIR})

# The user-facing programs. Not ndtom-microbench: a developer's tool that reads the test data
# from the source tree by a compiled-in path, and would add Google Benchmark to the package.
foreach(program ndtom-map ndtom-map-mpi ndtom-localize ndtom-slam ndtom-rawlog-from-pcd ndtom-eval ndtom-bench ndtom-regbench
    ndtom-worldgen)
  if(TARGET ${program})
    install(TARGETS ${program} RUNTIME DESTINATION ${CMAKE_INSTALL_BINDIR})
  endif()
endforeach()

# share/ndtom/mrpt: the .ini files for MRPT's programs; share/ndtom/data: the demo frames.
install(DIRECTORY ${PROJECT_SOURCE_DIR}/share/mrpt ${PROJECT_SOURCE_DIR}/share/data
        DESTINATION ${CMAKE_INSTALL_DATADIR}/ndtom)
