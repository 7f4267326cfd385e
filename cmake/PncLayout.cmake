# The relative layout shared by the install tree and the build tree (docs/install.md, D151).
# Included by the top-level CMakeLists.txt before the libraries: core/ compiles the relative
# directories in (pnc/core/locate.hpp), so that `pnc` finds its plot scripts and the LAMMPS
# stage server relative to its own executable, wherever the tree was installed or moved to.
include(GNUInstallDirs)

foreach(v BINDIR LIBDIR LIBEXECDIR DATADIR INCLUDEDIR)
  if(IS_ABSOLUTE "${CMAKE_INSTALL_${v}}")
    message(FATAL_ERROR "pnc: CMAKE_INSTALL_${v}='${CMAKE_INSTALL_${v}}' is absolute; the "
                        "installed tree is relocatable only with paths relative to the prefix "
                        "(docs/install.md)")
  endif()
endforeach()
if(CMAKE_INSTALL_BINDIR MATCHES "/")
  message(FATAL_ERROR "pnc: CMAKE_INSTALL_BINDIR='${CMAKE_INSTALL_BINDIR}' must be one "
                      "directory below the prefix (pnc finds <prefix>/share/pnc from <bin>/..)")
endif()

set(PNC_INSTALL_SCRIPTSDIR "${CMAKE_INSTALL_DATADIR}/pnc/scripts") # plot scripts
set(PNC_INSTALL_LIBEXECDIR "${CMAKE_INSTALL_LIBEXECDIR}/pnc")      # pnc_lammps_server
set(PNC_INSTALL_DOCDIR "${CMAKE_INSTALL_DATADIR}/doc/pnc")         # docs, examples, licence
set(PNC_INSTALL_CMAKEDIR "${CMAKE_INSTALL_LIBDIR}/cmake/pnc")      # pncConfig.cmake
set(PNC_INSTALL_PKGCONFIGDIR "${CMAKE_INSTALL_LIBDIR}/pkgconfig")  # pnc_material.pc
if(CMAKE_INSTALL_LIBEXECDIR MATCHES "/")
  message(FATAL_ERROR "pnc: CMAKE_INSTALL_LIBEXECDIR='${CMAKE_INSTALL_LIBEXECDIR}' must be "
                      "one directory below the prefix (like bin)")
endif()

# The plot scripts `pnc` and the GIMP driver run. In the build tree they are copied to
# <build>/share/pnc/scripts (configure_file: a changed script is copied again on the next
# build), which is <build>/app/../share/pnc/scripts as seen from <build>/app/pnc.
set(PNC_SHIPPED_SCRIPTS
    scripts/plot_figures.py scripts/plot_thermo.py scripts/plot_escm.py scripts/plot_drive.py
    gimp_coupler/scripts/plot_energy.py gimp_coupler/scripts/plot_G.py)
foreach(s IN LISTS PNC_SHIPPED_SCRIPTS)
  get_filename_component(n "${s}" NAME)
  configure_file("${PROJECT_SOURCE_DIR}/${s}" "${PROJECT_BINARY_DIR}/${PNC_INSTALL_SCRIPTSDIR}/${n}"
                 COPYONLY)
endforeach()

# RPATH of installed executables: $ORIGIN-relative, so that a moved tree still finds
# libpnc_material.so.1 (the GIMP solver in `pnc` links it).
file(RELATIVE_PATH PNC_BIN_TO_LIB "/p/${CMAKE_INSTALL_BINDIR}" "/p/${CMAKE_INSTALL_LIBDIR}")
file(RELATIVE_PATH PNC_LIBEXEC_TO_LIB "/p/${PNC_INSTALL_LIBEXECDIR}" "/p/${CMAKE_INSTALL_LIBDIR}")
