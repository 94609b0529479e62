# The pair term (forces/pair/): neighbour lists, pair kernels and the force field object.
target_sources(rotleap PRIVATE
  ${CMAKE_CURRENT_LIST_DIR}/neighbor.c
  ${CMAKE_CURRENT_LIST_DIR}/lj.c
  ${CMAKE_CURRENT_LIST_DIR}/coulomb_rf.c
  ${CMAKE_CURRENT_LIST_DIR}/dipole.c
  ${CMAKE_CURRENT_LIST_DIR}/quadrupole.c
  ${CMAKE_CURRENT_LIST_DIR}/forcefield.c
  ${CMAKE_CURRENT_LIST_DIR}/ff_fast.c
)
# The specialised kernels: `omp simd` loops (honoured even without OpenMP threads), sqrt
# without errno, and floating-point operations that may be evaluated speculatively (no traps
# are enabled), so that GCC can if-convert and vectorise the inner loops; none of these changes
# a result.  -ffp-contract=fast lets GCC fuse a * b + c into one FMA where the CPU has it
# (-std=c17 turns fusion off): the TIP4P loop is bound by its multiplies and adds (A/B with
# `ffbench time tip4p 2048 1 N` against a build without it).  A fused result is rounded once
# instead of twice, so the AVX2 and AVX-512 kernels differ from the scalar one in the last bits
# (test_ff_fast compares every kernel with the reference to 1e-12).
set_source_files_properties(${CMAKE_CURRENT_LIST_DIR}/ff_fast.c PROPERTIES
  COMPILE_OPTIONS "-fopenmp-simd;-fno-math-errno;-fno-trapping-math;-ffp-contract=fast")
# Sanitizer builds compile one portable instance per row function (no target clones, no
# AVX-512 or AVX2 register rows): GCC took over five minutes on ff_fast.c with every instance
# under ASan. The Release configurations test the register rows; this one checks the portable
# code. ROTLEAP_NO_CLONES does the same in any build (scripts/test.sh's build without OpenMP,
# which only checks that the library builds: ff_fast.c alone took 86 s with every instance).
if(ROTLEAP_SANITIZE OR ROTLEAP_NO_CLONES)
  set_property(SOURCE ${CMAKE_CURRENT_LIST_DIR}/ff_fast.c APPEND PROPERTY COMPILE_DEFINITIONS
    ROTLEAP_NO_CLONES)
endif()
