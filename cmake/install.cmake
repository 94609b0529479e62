# `cmake --install BUILD [--prefix PREFIX]`: the shared library (librotleap.so.0 ->
# librotleap.so.0.1.0), the public headers (include/rotleap/), a pkg-config file (rotleap.pc) and
# a CMake package (find_package(rotleap) gives the target rotleap::rotleap), and the command.
include(CMakePackageConfigHelpers)
install(TARGETS rotleap_shared EXPORT rotleapTargets
        LIBRARY DESTINATION ${CMAKE_INSTALL_LIBDIR}
        INCLUDES DESTINATION ${CMAKE_INSTALL_INCLUDEDIR})
install(TARGETS rotleap_cli RUNTIME DESTINATION ${CMAKE_INSTALL_BINDIR})
install(DIRECTORY ${PROJECT_SOURCE_DIR}/include/rotleap DESTINATION ${CMAKE_INSTALL_INCLUDEDIR}
        FILES_MATCHING PATTERN "*.h")
set(ROTLEAP_CMAKE_DIR ${CMAKE_INSTALL_LIBDIR}/cmake/rotleap)
install(EXPORT rotleapTargets NAMESPACE rotleap:: DESTINATION ${ROTLEAP_CMAKE_DIR})
configure_package_config_file(${CMAKE_CURRENT_LIST_DIR}/rotleapConfig.cmake.in
  ${CMAKE_CURRENT_BINARY_DIR}/rotleapConfig.cmake INSTALL_DESTINATION ${ROTLEAP_CMAKE_DIR})
write_basic_package_version_file(${CMAKE_CURRENT_BINARY_DIR}/rotleapConfigVersion.cmake
  COMPATIBILITY SameMajorVersion)
install(FILES ${CMAKE_CURRENT_BINARY_DIR}/rotleapConfig.cmake ${CMAKE_CURRENT_BINARY_DIR}/rotleapConfigVersion.cmake
        DESTINATION ${ROTLEAP_CMAKE_DIR})
# pkg-config: the paths relative to ${prefix}, so that the file holds for `--prefix` given at
# install time as well as for CMAKE_INSTALL_PREFIX
file(RELATIVE_PATH ROTLEAP_PC_UP /p/${CMAKE_INSTALL_LIBDIR}/pkgconfig /p)
configure_file(${CMAKE_CURRENT_LIST_DIR}/rotleap.pc.in ${CMAKE_CURRENT_BINARY_DIR}/rotleap.pc @ONLY)
install(FILES ${CMAKE_CURRENT_BINARY_DIR}/rotleap.pc DESTINATION ${CMAKE_INSTALL_LIBDIR}/pkgconfig)
