# Mesh load time (issue 3): generated ~1M-triangle GLB and glTF seabeds; assimp's bare ReadFile vs
# hadal's import_mesh (and compute_mesh_properties), measured in the same run.
add_executable(hadal_bench_mesh_load ${CMAKE_CURRENT_LIST_DIR}/mesh_load.cc)
target_compile_options(hadal_bench_mesh_load PRIVATE ${HADAL_WARNINGS})
target_link_libraries(hadal_bench_mesh_load PRIVATE hadal_mesh hadal_assets assimp::assimp)
