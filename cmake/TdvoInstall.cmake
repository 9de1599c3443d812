# Install rules (docs/api.md, "Installing and linking"): `cmake --install` puts the apps, the
# 3DVO libraries, their headers under include/tdvo/ (the source tree's paths: common/core/mesh.h,
# decoder/stream_decoder.h, ...), a CMake package (find_package(tdvo) with imported targets
# tdvo::core, tdvo::decoder, ...; components decoder, texture, encoder) and pkg-config files
# (tdvo-decoder.pc: geometry decoding alone; tdvo.pc: everything) in place.
include(GNUInstallDirs)
include(CMakePackageConfigHelpers)

# Registers an installed library; `component` is the package component it belongs to: decoder
# (geometry decoding: no video, image or JSON library), texture (the texture path: libpng,
# FFmpeg), encoder (needs both).
function(tdvo_library target component)
  string(REGEX REPLACE "^tdvo_" "" exportName "${target}")
  set_target_properties(${target} PROPERTIES EXPORT_NAME ${exportName})
  target_include_directories(${target} PUBLIC $<INSTALL_INTERFACE:${CMAKE_INSTALL_INCLUDEDIR}/tdvo>)
  install(TARGETS ${target} EXPORT tdvo-${component}-targets
    ARCHIVE DESTINATION ${CMAKE_INSTALL_LIBDIR}
    LIBRARY DESTINATION ${CMAKE_INSTALL_LIBDIR}
    RUNTIME DESTINATION ${CMAKE_INSTALL_BINDIR})
  set_property(GLOBAL APPEND PROPERTY TDVO_INSTALLED_LIBRARIES ${target})
  set_property(GLOBAL APPEND PROPERTY TDVO_COMPONENT_${component} ${exportName})
endfunction()

function(tdvo_install_package)
  # The apps, in bin/.
  install(TARGETS 3dvo-enc 3dvo-dec 3dvo-metrics 3dvo-sample 3dvo-render 3dvo-recon 3dvo-import
    3dvo-synth RUNTIME DESTINATION ${CMAKE_INSTALL_BINDIR})
  foreach(folder common bitstream decoder encoder)
    install(DIRECTORY ${PROJECT_SOURCE_DIR}/${folder}/ DESTINATION ${CMAKE_INSTALL_INCLUDEDIR}/tdvo/${folder}
      FILES_MATCHING PATTERN "*.h")
  endforeach()
  set(cmakeDir ${CMAKE_INSTALL_LIBDIR}/cmake/tdvo)
  foreach(component decoder texture encoder)
    install(EXPORT tdvo-${component}-targets NAMESPACE tdvo:: DESTINATION ${cmakeDir})
  endforeach()
  configure_package_config_file(${PROJECT_SOURCE_DIR}/cmake/tdvo-config.cmake.in
    ${PROJECT_BINARY_DIR}/tdvo-config.cmake INSTALL_DESTINATION ${cmakeDir})
  write_basic_package_version_file(${PROJECT_BINARY_DIR}/tdvo-config-version.cmake
    COMPATIBILITY SameMinorVersion)
  install(FILES ${PROJECT_BINARY_DIR}/tdvo-config.cmake ${PROJECT_BINARY_DIR}/tdvo-config-version.cmake
    DESTINATION ${cmakeDir})
  # pkg-config: tdvo-decoder.pc (the decoder component) and tdvo.pc (all), libraries in link
  # order (users first).
  get_property(libraries GLOBAL PROPERTY TDVO_INSTALLED_LIBRARIES)
  list(REVERSE libraries)
  get_property(decoderLibraries GLOBAL PROPERTY TDVO_COMPONENT_decoder)
  # Relocatable: the prefix is found from the .pc file's own folder (the install --prefix may
  # differ from CMAKE_INSTALL_PREFIX).
  file(RELATIVE_PATH TDVO_PC_UP "/${CMAKE_INSTALL_LIBDIR}/pkgconfig" "/")
  string(REGEX REPLACE "/$" "" TDVO_PC_UP "${TDVO_PC_UP}")
  foreach(pc tdvo tdvo-decoder)
    set(TDVO_PC_LIBS "")
    foreach(l ${libraries})
      string(REGEX REPLACE "^tdvo_" "" exportName "${l}")
      if(pc STREQUAL "tdvo" OR exportName IN_LIST decoderLibraries)
        string(APPEND TDVO_PC_LIBS " -l${l}")
      endif()
    endforeach()
    configure_file(${PROJECT_SOURCE_DIR}/cmake/${pc}.pc.in ${PROJECT_BINARY_DIR}/${pc}.pc @ONLY)
    install(FILES ${PROJECT_BINARY_DIR}/${pc}.pc DESTINATION ${CMAKE_INSTALL_LIBDIR}/pkgconfig)
  endforeach()
endfunction()
