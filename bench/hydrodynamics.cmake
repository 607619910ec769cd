# Surface hydrodynamics (issue 4): per-face force evaluations per second on one core for an ~11k-face
# torpedo hull, fully and partly submerged, all terms on; and soil contact per face in the same run.
add_executable(hadal_bench_hydrodynamics ${CMAKE_CURRENT_LIST_DIR}/hydrodynamics.cc)
target_compile_options(hadal_bench_hydrodynamics PRIVATE ${HADAL_WARNINGS})
target_link_libraries(hadal_bench_hydrodynamics PRIVATE hadal_hydrodynamics hadal_terramechanics hadal_mesh hadal_terrain hadal_assets)
