# The Ewald terms (forces/ewald/, issue 33): real space, classical Ewald, smooth PME (FFTW3).
find_package(PkgConfig REQUIRED)
pkg_check_modules(FFTW3 REQUIRED IMPORTED_TARGET fftw3)  # Debian libfftw3-dev
target_sources(rotleap PRIVATE
  ${CMAKE_CURRENT_LIST_DIR}/ewald_params.c
  ${CMAKE_CURRENT_LIST_DIR}/ewald_common.c
  ${CMAKE_CURRENT_LIST_DIR}/ewald_kspace.c
  ${CMAKE_CURRENT_LIST_DIR}/pme.c
  ${CMAKE_CURRENT_LIST_DIR}/ewald_real.c
)
target_link_libraries(rotleap PUBLIC PkgConfig::FFTW3)
# The real-space rows: `omp simd` loops (honoured without OpenMP threads too), sqrt without errno
# and speculative floating point so that GCC vectorises them; none of these changes a result.
# No -ffp-contract=fast: erfc.h's exact square of x relies on separate roundings.
set_source_files_properties(${CMAKE_CURRENT_LIST_DIR}/ewald_real.c PROPERTIES
  COMPILE_OPTIONS "-fopenmp-simd;-fno-math-errno;-fno-trapping-math")
if(ROTLEAP_SANITIZE OR ROTLEAP_NO_CLONES) # one portable instance, as forces/pair/pair.cmake does for its rows
  set_property(SOURCE ${CMAKE_CURRENT_LIST_DIR}/ewald_real.c APPEND PROPERTY COMPILE_DEFINITIONS ROTLEAP_NO_CLONES)
endif()
