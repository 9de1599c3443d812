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
  set_property(GLOBAL PROPERTY TDVO_COMPONENT_OF_${target} ${component})
endfunction()

# The shared variant of an installed library: the same object files (everything is compiled
# position-independent), linked against the shared variants of the 3DVO libraries it uses.
# Named lib<target>.so beside lib<target>.a; imported target tdvo::<name>_shared. Not made in
# sanitizer builds.
function(tdvo_shared_library target)
  string(REGEX REPLACE "^tdvo_" "" exportName "${target}")
  add_library(${target}_shared SHARED $<TARGET_OBJECTS:${target}>)
  set_target_properties(${target}_shared PROPERTIES OUTPUT_NAME ${target}
    EXPORT_NAME ${exportName}_shared VERSION ${PROJECT_VERSION}
    SOVERSION ${PROJECT_VERSION_MAJOR}.${PROJECT_VERSION_MINOR}
    INSTALL_RPATH "$ORIGIN")  # the other 3DVO libraries it uses are beside it
  target_include_directories(${target}_shared PUBLIC $<BUILD_INTERFACE:${PROJECT_SOURCE_DIR}>
    $<INSTALL_INTERFACE:${CMAKE_INSTALL_INCLUDEDIR}/tdvo>)
  get_target_property(all ${target} LINK_LIBRARIES)
  get_target_property(public ${target} INTERFACE_LINK_LIBRARIES)
  foreach(kind all public)
    set(mapped "")
    foreach(l ${${kind}})
      if(l MATCHES "^\\$<LINK_ONLY:")
        continue()
      elseif(TARGET ${l} AND l MATCHES "^tdvo_")
        list(APPEND mapped ${l}_shared)
      else()
        list(APPEND mapped ${l})
      endif()
    endforeach()
    set(${kind}Mapped ${mapped})
  endforeach()
  target_link_libraries(${target}_shared PUBLIC ${publicMapped} PRIVATE ${allMapped})
  get_property(component GLOBAL PROPERTY TDVO_COMPONENT_OF_${target})
  install(TARGETS ${target}_shared EXPORT tdvo-${component}-targets
    LIBRARY DESTINATION ${CMAKE_INSTALL_LIBDIR})
endfunction()

function(tdvo_install_package)
  get_property(installed GLOBAL PROPERTY TDVO_INSTALLED_LIBRARIES)
  if(NOT TDVO_SANITIZE AND NOT TDVO_FUZZ)
    foreach(l ${installed})
      tdvo_shared_library(${l})
    endforeach()
  endif()
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
