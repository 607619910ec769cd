# Ray casting (issue 3): Embree BVH build time and RaycastService throughput vs a bare rtcIntersect1
# loop on a generated ~1M-triangle seabed.
add_executable(hadal_bench_raycast ${CMAKE_CURRENT_LIST_DIR}/raycast.cc)
target_compile_options(hadal_bench_raycast PRIVATE ${HADAL_WARNINGS})
target_link_libraries(hadal_bench_raycast PRIVATE hadal_raycast embree Threads::Threads)
