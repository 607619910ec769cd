# Acoustic positioning (issue 42): what a USBL and an LBL cost the default scenario's step.
add_executable(hadal_bench_acoustics ${CMAKE_CURRENT_LIST_DIR}/acoustics.cc)
target_compile_options(hadal_bench_acoustics PRIVATE ${HADAL_WARNINGS})
target_compile_definitions(hadal_bench_acoustics PRIVATE HADAL_SOURCE_DIR="${PROJECT_SOURCE_DIR}")
target_link_libraries(hadal_bench_acoustics PRIVATE hadal_config hadal_sim)
