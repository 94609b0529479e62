# The pair term (forces/pair/): the force field and its reference routine, the pair lists, kernel
# selection, the kernels (one folder per instruction set, kernels/) and their threaded driver.
target_sources(rotleap PRIVATE
  ${CMAKE_CURRENT_LIST_DIR}/pairlist.c
  ${CMAKE_CURRENT_LIST_DIR}/lj.c
  ${CMAKE_CURRENT_LIST_DIR}/coulomb_rf.c
  ${CMAKE_CURRENT_LIST_DIR}/dipole.c
  ${CMAKE_CURRENT_LIST_DIR}/quadrupole.c
  ${CMAKE_CURRENT_LIST_DIR}/forcefield.c
)
# The specialised path: kernel selection, the kernels' list, the driver and the rows.
set(RL_PAIR_FAST_SOURCES
  ${CMAKE_CURRENT_LIST_DIR}/select.c
  ${CMAKE_CURRENT_LIST_DIR}/pairlist_rows.c
  ${CMAKE_CURRENT_LIST_DIR}/pairlist_images.c
  ${CMAKE_CURRENT_LIST_DIR}/driver.c
  ${CMAKE_CURRENT_LIST_DIR}/kernels/portable/sites_lj_rf.c
  ${CMAKE_CURRENT_LIST_DIR}/kernels/portable/tip4p_lj_rf.c
  ${CMAKE_CURRENT_LIST_DIR}/kernels/portable/dipole_lj_rf.c
  ${CMAKE_CURRENT_LIST_DIR}/kernels/portable/dipole_lj_sf.c
  ${CMAKE_CURRENT_LIST_DIR}/kernels/avx512/tip4p_lj_rf.c
  ${CMAKE_CURRENT_LIST_DIR}/kernels/avx512/dipole_lj_rf.c
  ${CMAKE_CURRENT_LIST_DIR}/kernels/avx512/dipole_lj_sf.c
  ${CMAKE_CURRENT_LIST_DIR}/kernels/avx2/tip4p_lj_rf.c
  ${CMAKE_CURRENT_LIST_DIR}/kernels/avx2/dipole_lj_rf.c
  ${CMAKE_CURRENT_LIST_DIR}/kernels/avx2/dipole_lj_sf.c
  ${CMAKE_CURRENT_LIST_DIR}/kernels/avx2_mixed/tip4p_lj_rf.c
  ${CMAKE_CURRENT_LIST_DIR}/kernels/portable/sites_lj_ewald.c
  ${CMAKE_CURRENT_LIST_DIR}/kernels/portable/tip4p_lj_ewald.c
  ${CMAKE_CURRENT_LIST_DIR}/kernels/avx512/tip4p_lj_ewald.c
  ${CMAKE_CURRENT_LIST_DIR}/kernels/avx2/tip4p_lj_ewald.c
  ${CMAKE_CURRENT_LIST_DIR}/kernels/portable/dipole_lj_ewald.c
  ${CMAKE_CURRENT_LIST_DIR}/kernels/avx512/dipole_lj_ewald.c
  ${CMAKE_CURRENT_LIST_DIR}/kernels/avx2/dipole_lj_ewald.c
)
target_sources(rotleap PRIVATE ${RL_PAIR_FAST_SOURCES})
# The specialised kernels: `omp simd` loops (honoured even without OpenMP threads), sqrt
# without errno, and floating-point operations that may be evaluated speculatively (no traps
# are enabled), so that GCC can if-convert and vectorise the inner loops; none of these changes
# a result.  -ffp-contract=fast lets GCC fuse a * b + c into one FMA where the CPU has it
# (-std=c17 turns fusion off): the TIP4P loop is bound by its multiplies and adds (A/B with
# `ffbench time tip4p 2048 1 N` against a build without it).  A fused result is rounded once
# instead of twice, so the AVX2 and AVX-512 kernels differ from the scalar one in the last bits
# (test_ff_fast compares every kernel with the reference to 1e-12).  The list build and the
# driver take the same flags: their minimum images and virial sums are fused alike.
set_source_files_properties(${RL_PAIR_FAST_SOURCES} PROPERTIES
  COMPILE_OPTIONS "-fopenmp-simd;-fno-math-errno;-fno-trapping-math;-ffp-contract=fast")
# Sanitizer builds compile one portable instance per row function (no target clones, no
# AVX-512 or AVX2 register rows): GCC took over five minutes on the pair rows with every instance
# under ASan. The Release configurations test the register rows; this one checks the portable
# code. ROTLEAP_NO_CLONES does the same in any build (scripts/test.sh's build without OpenMP,
# which only checks that the library builds).
if(ROTLEAP_SANITIZE OR ROTLEAP_NO_CLONES)
  set_property(SOURCE ${RL_PAIR_FAST_SOURCES} APPEND PROPERTY COMPILE_DEFINITIONS
    ROTLEAP_NO_CLONES)
endif()
# In the sanitizer build the rows are under AddressSanitizer but not UBSan: their loops are
# floating-point arithmetic on indices the list build (under both) produced, and UBSan's checks
# of every integer and pointer operation in those long inlined loops took 60 % of GCC's time on
# them (kernels/portable/tip4p_lj_rf.c: 26.7 s of CPU with, 11.0 s without) and slowed the
# sanitizer pass's force-heavy tests, in a test command that has to stay under 10 minutes.
# Out-of-bounds reads and writes in the rows are still trapped (ASan).
if(ROTLEAP_SANITIZE)
  set_property(SOURCE ${RL_PAIR_FAST_SOURCES} APPEND PROPERTY COMPILE_OPTIONS -fno-sanitize=undefined)
endif()
