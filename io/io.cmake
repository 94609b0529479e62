# File I/O: trajectories (DCD, PDB, extended XYZ), starting states and checkpoints.
# No extra libraries: CRC-32 is implemented in io/io_common.c; the PDB fit uses GSL (already linked).
target_sources(rotleap PRIVATE
  ${CMAKE_CURRENT_LIST_DIR}/io_common.c
  ${CMAKE_CURRENT_LIST_DIR}/io_dcd.c
  ${CMAKE_CURRENT_LIST_DIR}/io_pdb.c
  ${CMAKE_CURRENT_LIST_DIR}/io_xyz.c
  ${CMAKE_CURRENT_LIST_DIR}/io_checkpoint.c
)
