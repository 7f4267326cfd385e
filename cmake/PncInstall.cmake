# Install rules and the Debian package (docs/install.md, decisions D150-D159).
#
#   cmake --install build --prefix P       P/bin/pnc, P/libexec/pnc/pnc_lammps_server,
#                                          P/lib/libpnc_material.so*, P/include/pnc/fe_material/,
#                                          P/lib/cmake/pnc/ (pnc::material, pnc::material_headers,
#                                          pnc::pnc), P/lib/pkgconfig/pnc_material.pc,
#                                          P/share/pnc/scripts/, P/share/doc/pnc/
#   cpack --config build/CPackConfig.cmake  pnc_<version>_<arch>.deb of the same tree under /usr
#
# Every rule is guarded by the presence of its target: a partial build (scripts/sanitize.sh's
# build-asan/ has no LAMMPS, hence no stage server) still configures. The version is the
# project()'s (written once, top-level CMakeLists.txt); the plugin's ABI version is
# PNC_MATERIAL_ABI_VERSION of pnc_material.h (fe_material/CMakeLists.txt reads it).
include(CMakePackageConfigHelpers)

# --- executables
if(TARGET pnc)
  install(TARGETS pnc EXPORT pncTargets RUNTIME DESTINATION ${CMAKE_INSTALL_BINDIR})
endif()
if(TARGET pnc_lammps_server)
  # an internal helper started by `pnc` under mpirun, not a user command: libexec (D152)
  install(TARGETS pnc_lammps_server RUNTIME DESTINATION ${PNC_INSTALL_LIBEXECDIR})
endif()

# --- the material plugin and its headers
# (the include directory comes from pnc_material_headers' $<INSTALL_INTERFACE:...>)
install(TARGETS pnc_material pnc_material_headers EXPORT pncTargets
  LIBRARY DESTINATION ${CMAKE_INSTALL_LIBDIR})
install(FILES fe_material/include/pnc/fe_material/pnc_material.h
              fe_material/include/pnc/fe_material/umat.h
              fe_material/include/pnc/fe_material/material.hpp
              fe_material/include/pnc/fe_material/material_api.hpp
        DESTINATION ${CMAKE_INSTALL_INCLUDEDIR}/pnc/fe_material)

# --- CMake package: find_package(pnc) (D155)
install(EXPORT pncTargets NAMESPACE pnc:: DESTINATION ${PNC_INSTALL_CMAKEDIR}
        FILE pncTargets.cmake)
configure_package_config_file(cmake/pncConfig.cmake.in ${PROJECT_BINARY_DIR}/pncConfig.cmake
  INSTALL_DESTINATION ${PNC_INSTALL_CMAKEDIR}
  PATH_VARS PNC_INSTALL_SCRIPTSDIR PNC_INSTALL_DOCDIR)
# 0.x: a minor version may break the interface, so only the same MAJOR.MINOR is compatible
write_basic_package_version_file(${PROJECT_BINARY_DIR}/pncConfigVersion.cmake
  VERSION ${PROJECT_VERSION} COMPATIBILITY SameMinorVersion)
install(FILES ${PROJECT_BINARY_DIR}/pncConfig.cmake ${PROJECT_BINARY_DIR}/pncConfigVersion.cmake
        DESTINATION ${PNC_INSTALL_CMAKEDIR})

# --- pkg-config: relocatable through ${pcfiledir} (D155)
file(RELATIVE_PATH PNC_PC_TO_PREFIX "/p/${PNC_INSTALL_PKGCONFIGDIR}" "/p")
string(REGEX REPLACE "/$" "" PNC_PC_TO_PREFIX "${PNC_PC_TO_PREFIX}")
configure_file(cmake/pnc_material.pc.in ${PROJECT_BINARY_DIR}/pnc_material.pc @ONLY)
install(FILES ${PROJECT_BINARY_DIR}/pnc_material.pc DESTINATION ${PNC_INSTALL_PKGCONFIGDIR})

# --- plot scripts (found by pnc relative to its executable, D151)
foreach(s IN LISTS PNC_SHIPPED_SCRIPTS)
  install(FILES ${s} DESTINATION ${PNC_INSTALL_SCRIPTSDIR})
endforeach()

# --- documentation, examples, licence (README's relative links keep working there)
install(FILES README.md LICENSE CITATION.cff DESTINATION ${PNC_INSTALL_DOCDIR})
install(DIRECTORY docs/ DESTINATION ${PNC_INSTALL_DOCDIR}/docs FILES_MATCHING PATTERN "*.md"
                                                                   PATTERN "*.schema.json")
install(DIRECTORY examples/ DESTINATION ${PNC_INSTALL_DOCDIR}/examples)

# --- the Debian package (D156): `cpack` in the build directory
set(CPACK_GENERATOR DEB)
set(CPACK_PACKAGE_NAME pnc)
set(CPACK_PACKAGE_VERSION ${PROJECT_VERSION})
set(CPACK_PACKAGE_VENDOR "The pnc developers")
set(CPACK_PACKAGE_CONTACT "The pnc developers")
set(CPACK_PACKAGE_DESCRIPTION_SUMMARY
    "multiscale toolkit for polymer nanocomposites: MD -> fitted damage law -> material plugin")
set(CPACK_PACKAGE_DESCRIPTION
    "pnc fits the nano-scale damage model (Nair 2010) to stress-strain curves of molecular \
simulations (LAMMPS), writes HDF5 material cards and ships the law as a material plugin \
(libpnc_material.so: C ABI, Abaqus-style umat_, C++ wrapper) with its CMake and pkg-config \
files, plus a GIMP solver and a GIMP-MD coupling.")
set(CPACK_RESOURCE_FILE_LICENSE ${PROJECT_SOURCE_DIR}/LICENSE)
set(CPACK_PACKAGING_INSTALL_PREFIX /usr)
set(CPACK_STRIP_FILES ON)
set(CPACK_DEBIAN_FILE_NAME DEB-DEFAULT) # pnc_<version>_<arch>.deb
set(CPACK_DEBIAN_PACKAGE_SECTION science)
set(CPACK_DEBIAN_PACKAGE_SHLIBDEPS ON) # Depends of every ELF file from dpkg-shlibdeps
# (libpnc_material.so.1, which `pnc` links, is this package's own: dpkg-shlibdeps finds it
# through the $ORIGIN RPATH inside the package tree)
set(CPACK_DEBIAN_PACKAGE_GENERATE_SHLIBS ON) # shlibs file + ldconfig trigger for the plugin
# What shlibdeps cannot see: the plot scripts' interpreter and matplotlib (pnc fit draws
# plots by default); mpirun only for stages on several ranks (--ranks K > 1).
set(CPACK_DEBIAN_PACKAGE_DEPENDS "python3, python3-matplotlib")
set(CPACK_DEBIAN_PACKAGE_RECOMMENDS "openmpi-bin")
include(CPack)
