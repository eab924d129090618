# Run by the build (tools/vision/CMakeLists.txt): converts what scripts/setup fetched.
file(MAKE_DIRECTORY ${OUT})
execute_process(
  COMMAND ${CONVERT} ${FETCHED}/face_recognition_model-weights_manifest.json
          ${FETCHED}/face_recognition_model.bin ${OUT}/face_recognition.mvt
  RESULT_VARIABLE rc)
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "converting the face recognition model failed (run scripts/setup again)")
endif()
# The BlazeFace ONNX files load in OpenCV as they are.
file(COPY_FILE ${FETCHED}/face_detection_back_256x256_barracuda.onnx ${OUT}/blazeface_back_256.onnx)
file(COPY_FILE ${FETCHED}/face_detection_front_128x128_barracuda.onnx ${OUT}/blazeface_front_128.onnx)
