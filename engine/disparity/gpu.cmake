# The GPU passes of the disparity pipeline (beside their CPU reference).
add_library(vg_disparity_gpu STATIC
  ${CMAKE_CURRENT_LIST_DIR}/disparity_gpu.c
  ${CMAKE_CURRENT_LIST_DIR}/keyframe_gpu.c
  ${CMAKE_CURRENT_LIST_DIR}/metrics_gpu.c
  ${CMAKE_CURRENT_LIST_DIR}/operator_gpu.c
  ${CMAKE_CURRENT_LIST_DIR}/solve_gpu.c
  ${CMAKE_CURRENT_LIST_DIR}/upsample_gpu.c)
target_link_libraries(vg_disparity_gpu PUBLIC vg_render vg_disparity PRIVATE PkgConfig::CGLM)
