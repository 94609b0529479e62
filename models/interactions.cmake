# Interactions (issue 4): box, neighbour lists, pair kernels and the force field object.
target_sources(rotleap PRIVATE
  ${CMAKE_CURRENT_LIST_DIR}/../core/box.c
  ${CMAKE_CURRENT_LIST_DIR}/../core/neighbor.c
  ${CMAKE_CURRENT_LIST_DIR}/lj.c
  ${CMAKE_CURRENT_LIST_DIR}/coulomb_rf.c
  ${CMAKE_CURRENT_LIST_DIR}/dipole.c
  ${CMAKE_CURRENT_LIST_DIR}/quadrupole.c
  ${CMAKE_CURRENT_LIST_DIR}/forcefield.c
  ${CMAKE_CURRENT_LIST_DIR}/ff_fast.c
)
# The specialised kernels: `omp simd` loops (honoured even without OpenMP threads), sqrt
# without errno, and floating-point operations that may be evaluated speculatively (no traps
# are enabled), so that GCC can if-convert and vectorise the inner loops.  None changes a result.
set_source_files_properties(${CMAKE_CURRENT_LIST_DIR}/ff_fast.c PROPERTIES
  COMPILE_OPTIONS "-fopenmp-simd;-fno-math-errno;-fno-trapping-math")
