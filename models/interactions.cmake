# Interactions (issue 4): box, neighbour lists, pair kernels and the force field object.
target_sources(rotleap PRIVATE
  ${CMAKE_CURRENT_LIST_DIR}/../core/box.c
  ${CMAKE_CURRENT_LIST_DIR}/../core/neighbor.c
  ${CMAKE_CURRENT_LIST_DIR}/lj.c
  ${CMAKE_CURRENT_LIST_DIR}/coulomb_rf.c
  ${CMAKE_CURRENT_LIST_DIR}/dipole.c
  ${CMAKE_CURRENT_LIST_DIR}/quadrupole.c
  ${CMAKE_CURRENT_LIST_DIR}/forcefield.c
)
