# Binary package for Debian 12: `cpack -G DEB` in the build directory
# writes linkscape_<version>_amd64.deb. Included at the end of the top-level
# CMakeLists.txt, so every install() rule of the project is known here.
#
# Depends is computed by dpkg-shlibdeps (package dpkg-dev) from the shared
# libraries the installed binary really links (Qt6, VTK 9.1, OpenMP, Highway
# (libhwy1, the SIMD dispatch of the field kernels), ...).
# On Debian 12 the Qt xcb platform plugin ships in libqt6gui6, which
# shlibdeps already pulls in, so nothing is dlopen()ed from another package.
# check-deb.sh builds and inspects the package without installing it.

set(CPACK_PACKAGE_NAME "linkscape")
set(CPACK_PACKAGE_VENDOR "Linkscape developers")
# Whoever ships the package puts their address here (-DLINKSCAPE_PACKAGE_CONTACT=...);
# the default's reserved .invalid domain (RFC 2606) says plainly that it reaches nobody.
set(LINKSCAPE_PACKAGE_CONTACT "Linkscape developers <linkscape@packages.invalid>" CACHE STRING
    "Maintainer of the .deb, Name <address>")
set(CPACK_PACKAGE_CONTACT "${LINKSCAPE_PACKAGE_CONTACT}")
set(CPACK_PACKAGE_VERSION "${PROJECT_VERSION}")
set(CPACK_PACKAGE_DESCRIPTION_SUMMARY
    "Kinematic design of parallel haptic-device mechanisms")
set(CPACK_PACKAGE_DESCRIPTION
    "Pick a mechanism, drag its actuator angles and link lengths, and see the
linkage move, its Jacobian condition number and its workspace. The same
engine runs headless (linkscape eval, slice, field, mesh, fit) to evaluate
kinematics in bulk, export condition-number slices, sampled volumes for
ParaView and workspace meshes, and size a device to a task.

Includes the 3-DOF 12R parallel hand controller, the 7-DOF PATHOS-II
device and a rotary Delta.")
# No project homepage: keep CPack from inventing one.
unset(CPACK_PACKAGE_HOMEPAGE_URL)
set(CPACK_PACKAGE_HOMEPAGE_URL "")

if(NOT CPACK_GENERATOR)
  set(CPACK_GENERATOR "DEB")
endif()
set(CPACK_PACKAGING_INSTALL_PREFIX "/usr")
set(CPACK_STRIP_FILES ON)

# DEB generator
set(CPACK_DEBIAN_FILE_NAME DEB-DEFAULT)         # linkscape_<version>_<arch>.deb
set(CPACK_DEBIAN_PACKAGE_MAINTAINER "${LINKSCAPE_PACKAGE_CONTACT}")
set(CPACK_DEBIAN_PACKAGE_SECTION "science")
set(CPACK_DEBIAN_PACKAGE_PRIORITY "optional")
# Description: CPack puts CPACK_PACKAGE_DESCRIPTION_SUMMARY on the first line
# and CPACK_PACKAGE_DESCRIPTION below it.
set(CPACK_DEBIAN_PACKAGE_SHLIBDEPS ON)
# Rendering needs a working OpenGL driver; Mesa's is the usual one, but a
# vendor driver will do, so it is only recommended.
set(CPACK_DEBIAN_PACKAGE_RECOMMENDS "libgl1-mesa-dri")
# libmpi comes in through SHLIBDEPS where the binary links it; mpirun, to run
# linkscape sweep over several processes, is only suggested.
set(CPACK_DEBIAN_PACKAGE_SUGGESTS "openmpi-bin")

# Source tarball (cpack --config CPackSourceConfig.cmake): leave out build
# trees and VCS data.
set(CPACK_SOURCE_GENERATOR "TGZ")
set(CPACK_SOURCE_IGNORE_FILES
    "/\\\\.git/" "/\\\\.cache/" "/build[^/]*/" "/_CPack_Packages/" "\\\\.deb$" "~$")

include(CPack)
