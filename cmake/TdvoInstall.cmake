# Install rules (docs/api.md, "Installing and linking"): `cmake --install` puts the 3DVO
# libraries, their headers under include/tdvo/ (the source tree's paths: common/core/mesh.h,
# decoder/stream_decoder.h, ...), a CMake package (find_package(tdvo) with imported targets
# tdvo::core, tdvo::decoder, ...) and a pkg-config file (tdvo.pc) in place.
include(GNUInstallDirs)
include(CMakePackageConfigHelpers)

# Registers an installed library; `component` is the package component it belongs to (core: what
# geometry coding needs; texture: the texture path's media libraries).
function(tdvo_library target component)
  string(REGEX REPLACE "^tdvo_" "" exportName "${target}")
  set_target_properties(${target} PROPERTIES EXPORT_NAME ${exportName})
  target_include_directories(${target} PUBLIC $<INSTALL_INTERFACE:${CMAKE_INSTALL_INCLUDEDIR}/tdvo>)
  install(TARGETS ${target} EXPORT tdvo-targets
    ARCHIVE DESTINATION ${CMAKE_INSTALL_LIBDIR}
    LIBRARY DESTINATION ${CMAKE_INSTALL_LIBDIR}
    RUNTIME DESTINATION ${CMAKE_INSTALL_BINDIR})
  set_property(GLOBAL APPEND PROPERTY TDVO_INSTALLED_LIBRARIES ${target})
  set_property(GLOBAL APPEND PROPERTY TDVO_COMPONENT_${component} ${exportName})
endfunction()

function(tdvo_install_package)
  foreach(folder common bitstream decoder encoder)
    install(DIRECTORY ${PROJECT_SOURCE_DIR}/${folder}/ DESTINATION ${CMAKE_INSTALL_INCLUDEDIR}/tdvo/${folder}
      FILES_MATCHING PATTERN "*.h")
  endforeach()
  set(cmakeDir ${CMAKE_INSTALL_LIBDIR}/cmake/tdvo)
  install(EXPORT tdvo-targets NAMESPACE tdvo:: DESTINATION ${cmakeDir})
  get_property(core GLOBAL PROPERTY TDVO_COMPONENT_core)
  get_property(texture GLOBAL PROPERTY TDVO_COMPONENT_texture)
  configure_package_config_file(${PROJECT_SOURCE_DIR}/cmake/tdvo-config.cmake.in
    ${PROJECT_BINARY_DIR}/tdvo-config.cmake INSTALL_DESTINATION ${cmakeDir})
  write_basic_package_version_file(${PROJECT_BINARY_DIR}/tdvo-config-version.cmake
    COMPATIBILITY SameMinorVersion)
  install(FILES ${PROJECT_BINARY_DIR}/tdvo-config.cmake ${PROJECT_BINARY_DIR}/tdvo-config-version.cmake
    DESTINATION ${cmakeDir})
  # pkg-config: one file for the whole library, libraries in link order (users first).
  get_property(libraries GLOBAL PROPERTY TDVO_INSTALLED_LIBRARIES)
  list(REVERSE libraries)
  set(TDVO_PC_LIBS "")
  foreach(l ${libraries})
    string(APPEND TDVO_PC_LIBS " -l${l}")
  endforeach()
  # Relocatable: the prefix is found from the .pc file's own folder (the install --prefix may
  # differ from CMAKE_INSTALL_PREFIX).
  file(RELATIVE_PATH TDVO_PC_UP "/${CMAKE_INSTALL_LIBDIR}/pkgconfig" "/")
  string(REGEX REPLACE "/$" "" TDVO_PC_UP "${TDVO_PC_UP}")
  configure_file(${PROJECT_SOURCE_DIR}/cmake/tdvo.pc.in ${PROJECT_BINARY_DIR}/tdvo.pc @ONLY)
  install(FILES ${PROJECT_BINARY_DIR}/tdvo.pc DESTINATION ${CMAKE_INSTALL_LIBDIR}/pkgconfig)
endfunction()
