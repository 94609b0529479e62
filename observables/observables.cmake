# Observables (issue 5): block averages, fluctuation formulas, RDFs, correlation functions,
# diffusion, dipoles and the dielectric constant.  Included by the top-level CMakeLists.txt.
target_sources(rotleap PRIVATE
  ${CMAKE_CURRENT_LIST_DIR}/observables_stats.c
  ${CMAKE_CURRENT_LIST_DIR}/observables_rdf.c
  ${CMAKE_CURRENT_LIST_DIR}/observables_tcf.c
  ${CMAKE_CURRENT_LIST_DIR}/observables_dielectric.c
)
