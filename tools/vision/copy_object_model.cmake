# Run by the build (tools/vision/CMakeLists.txt): NanoDet's TF.js graph model, which
# core/vision/tfjs_graph.cpp loads as it is. Without it (scripts/setup not run since it was
# added) nothing is copied and the detector names the missing file and scripts/setup.
if(EXISTS ${FETCHED}/nanodet.json AND EXISTS ${FETCHED}/nanodet.bin)
  file(MAKE_DIRECTORY ${OUT})
  file(COPY_FILE ${FETCHED}/nanodet.json ${OUT}/nanodet.json ONLY_IF_DIFFERENT)
  file(COPY_FILE ${FETCHED}/nanodet.bin ${OUT}/nanodet.bin ONLY_IF_DIFFERENT)
endif()
