# Cameras (issue 11): one deep-sea frame (radiance, depth, counts) over a ~1M-triangle seabed.
add_executable(hadal_bench_render ${CMAKE_CURRENT_LIST_DIR}/render.cc)
target_compile_options(hadal_bench_render PRIVATE ${HADAL_WARNINGS})
target_link_libraries(hadal_bench_render PRIVATE hadal_render hadal_sensors embree Threads::Threads)
