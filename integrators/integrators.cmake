# The integrators (integrators/): the rotation solves and baseline kernels, the leapfrog core,
# the rotation path of each model family (integrators/paths/) and the step operators
# (integrators/stepops/: thermostats, later barostats).  A new path or operator is one file here.
target_sources(rotleap PRIVATE
  ${CMAKE_CURRENT_LIST_DIR}/rotation.c
  ${CMAKE_CURRENT_LIST_DIR}/baselines.c
  ${CMAKE_CURRENT_LIST_DIR}/leapfrog.c
  ${CMAKE_CURRENT_LIST_DIR}/paths/common.c
  ${CMAKE_CURRENT_LIST_DIR}/paths/point.c
  ${CMAKE_CURRENT_LIST_DIR}/paths/dipole.c
  ${CMAKE_CURRENT_LIST_DIR}/paths/linear.c
  ${CMAKE_CURRENT_LIST_DIR}/paths/spherical.c
  ${CMAKE_CURRENT_LIST_DIR}/paths/symmetric.c
  ${CMAKE_CURRENT_LIST_DIR}/paths/asymmetric.c
  ${CMAKE_CURRENT_LIST_DIR}/paths/baselines.c
  ${CMAKE_CURRENT_LIST_DIR}/stepops/common.c
  ${CMAKE_CURRENT_LIST_DIR}/stepops/isokinetic.c
  ${CMAKE_CURRENT_LIST_DIR}/stepops/bussi.c
  ${CMAKE_CURRENT_LIST_DIR}/stepops/langevin.c
)
