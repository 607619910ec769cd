# Cables (issue 43): what a lumped-mass cable costs per physics step, and its real-time factor on one thread.
add_executable(hadal_bench_cables ${CMAKE_CURRENT_LIST_DIR}/cables.cc)
target_compile_options(hadal_bench_cables PRIVATE ${HADAL_WARNINGS})
target_link_libraries(hadal_bench_cables PRIVATE hadal_physics)
