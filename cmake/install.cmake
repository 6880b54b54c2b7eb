# cmake --install BUILD --prefix PREFIX: the command-line tool (bin/), the shared library (lib/),
# its plugins (lib/flipflux/),
# the public headers (include/flipflux/), the golden data and the report generator
# (share/flipflux/), a CMake package (lib/cmake/flipflux: find_package(flipflux CONFIG REQUIRED)
# -> flipflux::flipflux) and a pkg-config file (lib/pkgconfig/flipflux.pc). Everything is
# relocatable: nothing records the prefix given at configure time.
include(GNUInstallDirs)
include(CMakePackageConfigHelpers)

install(TARGETS flipflux_cli RUNTIME DESTINATION ${CMAKE_INSTALL_BINDIR})
# the plugins (core/plugin.hpp), found from BINDIR and LIBDIR
install(TARGETS flipflux_ceres flipflux_mpi LIBRARY DESTINATION ${CMAKE_INSTALL_LIBDIR}/flipflux)
install(TARGETS flipflux_shared flipflux_deps EXPORT flipflux-targets
        LIBRARY DESTINATION ${CMAKE_INSTALL_LIBDIR}
        INCLUDES DESTINATION ${CMAKE_INSTALL_INCLUDEDIR})
install(DIRECTORY ${PROJECT_SOURCE_DIR}/include/flipflux DESTINATION ${CMAKE_INSTALL_INCLUDEDIR})
install(PROGRAMS ${PROJECT_SOURCE_DIR}/tools/report/make_report.py
        DESTINATION ${CMAKE_INSTALL_DATADIR}/flipflux/report)
install(FILES ${PROJECT_SOURCE_DIR}/tools/report/statistics_sections.py
              ${PROJECT_SOURCE_DIR}/tools/report/report_common.py
              ${PROJECT_SOURCE_DIR}/tools/report/report_loading.py
              ${PROJECT_SOURCE_DIR}/tools/report/report_figures.py
              ${PROJECT_SOURCE_DIR}/tools/report/report_tables.py
        DESTINATION ${CMAKE_INSTALL_DATADIR}/flipflux/report)
install(DIRECTORY ${PROJECT_SOURCE_DIR}/data/golden/ DESTINATION ${CMAKE_INSTALL_DATADIR}/flipflux/golden)

set(FLIPFLUX_CMAKE_DIR ${CMAKE_INSTALL_LIBDIR}/cmake/flipflux)
install(EXPORT flipflux-targets NAMESPACE flipflux:: DESTINATION ${FLIPFLUX_CMAKE_DIR})
configure_package_config_file(${PROJECT_SOURCE_DIR}/cmake/flipflux-config.cmake.in
                              ${PROJECT_BINARY_DIR}/flipflux-config.cmake
                              INSTALL_DESTINATION ${FLIPFLUX_CMAKE_DIR}
                              PATH_VARS CMAKE_INSTALL_DATADIR)
write_basic_package_version_file(${PROJECT_BINARY_DIR}/flipflux-config-version.cmake
                                 COMPATIBILITY SameMinorVersion)
install(FILES ${PROJECT_BINARY_DIR}/flipflux-config.cmake
              ${PROJECT_BINARY_DIR}/flipflux-config-version.cmake
        DESTINATION ${FLIPFLUX_CMAKE_DIR})

# pkg-config: the prefix is found from the .pc file's own place (${pcfiledir}).
file(RELATIVE_PATH FLIPFLUX_PC_TO_PREFIX ${CMAKE_INSTALL_FULL_LIBDIR}/pkgconfig ${CMAKE_INSTALL_PREFIX})
string(REGEX REPLACE "/$" "" FLIPFLUX_PC_TO_PREFIX "${FLIPFLUX_PC_TO_PREFIX}")
configure_file(${PROJECT_SOURCE_DIR}/cmake/flipflux.pc.in ${PROJECT_BINARY_DIR}/flipflux.pc @ONLY)
install(FILES ${PROJECT_BINARY_DIR}/flipflux.pc DESTINATION ${CMAKE_INSTALL_LIBDIR}/pkgconfig)
