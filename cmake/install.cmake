# `cmake --install`: the command, the report renderer beside it
# (share/hapticbench/reports, found from the binary's folder), the public
# headers (include/hapticbench/), the two libraries a renderer links (core,
# proxy; position-independent so that a plugin module can hold them) and a
# package config with exported targets: hapticbench::renderer, and
# hapticbench_add_plugin() for plugin projects (docs/plugins.md). `cpack -G
# DEB` packs the same files as a Debian package.
include(GNUInstallDirs)
include(CMakePackageConfigHelpers)

add_library(hb_renderer_api INTERFACE)
target_link_libraries(hb_renderer_api INTERFACE hb_core hb_proxy)
add_library(hapticbench::renderer ALIAS hb_renderer_api)
set_target_properties(hb_core PROPERTIES EXPORT_NAME core)
set_target_properties(hb_proxy PROPERTIES EXPORT_NAME proxy)
set_target_properties(hb_renderer_api PROPERTIES EXPORT_NAME renderer)
target_include_directories(hb_core PUBLIC $<INSTALL_INTERFACE:${CMAKE_INSTALL_INCLUDEDIR}>)

install(TARGETS hapticbench RUNTIME DESTINATION ${CMAKE_INSTALL_BINDIR})
install(TARGETS hb_core hb_proxy hb_renderer_api EXPORT hapticbenchTargets
  ARCHIVE DESTINATION ${CMAKE_INSTALL_LIBDIR})
install(DIRECTORY include/hapticbench DESTINATION ${CMAKE_INSTALL_INCLUDEDIR})
set(hb_reports_destination ${CMAKE_INSTALL_DATADIR}/hapticbench/reports)
install(PROGRAMS reports/render_report.py DESTINATION ${hb_reports_destination})
install(FILES reports/report_template.html DESTINATION ${hb_reports_destination})
install(DIRECTORY reports/hapticbench_report DESTINATION ${hb_reports_destination}
  FILES_MATCHING PATTERN "*.py")

set(hb_package_destination ${CMAKE_INSTALL_LIBDIR}/cmake/hapticbench)
install(EXPORT hapticbenchTargets NAMESPACE hapticbench:: DESTINATION ${hb_package_destination})
configure_package_config_file(cmake/hapticbenchConfig.cmake.in
  ${CMAKE_CURRENT_BINARY_DIR}/hapticbenchConfig.cmake
  INSTALL_DESTINATION ${hb_package_destination} PATH_VARS CMAKE_INSTALL_BINDIR)
# 0.x: a plugin needs the same minor version (kPluginAbiVersion, plugin.h).
write_basic_package_version_file(${CMAKE_CURRENT_BINARY_DIR}/hapticbenchConfigVersion.cmake
  COMPATIBILITY SameMinorVersion)
install(FILES ${CMAKE_CURRENT_BINARY_DIR}/hapticbenchConfig.cmake
  ${CMAKE_CURRENT_BINARY_DIR}/hapticbenchConfigVersion.cmake cmake/hapticbench_plugin.cmake
  DESTINATION ${hb_package_destination})

set(CPACK_PACKAGE_NAME hapticbench)
set(CPACK_PACKAGE_CONTACT "hapticbench maintainers")
set(CPACK_PACKAGE_DESCRIPTION_SUMMARY "benchmarks and validates 6-DOF haptic rendering algorithms")
set(CPACK_DEBIAN_PACKAGE_SHLIBDEPS ON)
set(CPACK_DEBIAN_PACKAGE_DEPENDS "libeigen3-dev, python3-matplotlib")
set(CPACK_DEBIAN_FILE_NAME DEB-DEFAULT)
set(CPACK_GENERATOR DEB)
include(CPack)
