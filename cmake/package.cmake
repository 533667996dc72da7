# `cpack -G DEB` in the build folder: one Debian package with the programs, the plugin, the
# libraries, headers, CMake package and share/ndtom. Runtime dependencies come from
# dpkg-shlibdeps; the -dev packages the headers and the CMake package need are declared here.
set(CPACK_PACKAGE_NAME ndtom)
set(CPACK_PACKAGE_VENDOR "NDT-OM for MRPT")
set(CPACK_PACKAGE_CONTACT "NDT-OM for MRPT maintainers <maintainers@users.noreply.h-seed-fac8c0ef.example>")
set(CPACK_PACKAGE_DESCRIPTION_SUMMARY
    "Normal Distributions Transform Occupancy Maps: C++ library, MRPT plugin and programs")
set(CPACK_PACKAGE_VERSION ${PROJECT_VERSION})
set(CPACK_PACKAGING_INSTALL_PREFIX /usr)
set(CPACK_STRIP_FILES ON)

set(CPACK_DEBIAN_FILE_NAME DEB-DEFAULT)
set(CPACK_DEBIAN_PACKAGE_SECTION science)
set(CPACK_DEBIAN_PACKAGE_SHLIBDEPS ON)
# The core's headers need Eigen; ndtom_io and the MRPT plugin are found only when OpenCV and
# MRPT's development packages are installed (the programs need just their runtime libraries).
set(CPACK_DEBIAN_PACKAGE_DEPENDS "libeigen3-dev (>= 3.4)")
set(CPACK_DEBIAN_PACKAGE_RECOMMENDS "libmrpt-dev (>= 2.5), libopencv-dev (>= 4), mrpt-apps")
include(CPack)
