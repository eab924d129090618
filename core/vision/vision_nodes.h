// Graph nodes of the vision pipeline (core/graph), registered by name for graphs in JSON
// (examples/graphs/vision_faces.json):
//
//   CameraSource        -> frames (VideoFrame)
//       camera (required): "folder:DIR", "video:FILE", "device:/dev/video0" or "device:0"
//       (see open_camera()); width (640), height (480), fps (30); pace_fps (0 = as fast as
//       the camera delivers; a folder or video is otherwise read as fast as possible);
//       loop (false: a folder or video ends the source at its end); retry_ms (1000);
//       max_frames (0 = no limit).
//       A camera that fails to open or vanishes is logged (warning, naming the device) and
//       opened again every retry_ms; the graph keeps running, and a watchdog deadline on the
//       frames stream reports the silence. Wire it to a drop_oldest stream: a slow detector
//       then sees the newest frame, not a backlog.
//   FaceDetectorNode    in (VideoFrame) -> out (FaceList)
//       detector ("blazeface": the back model; "blazeface-front", "haar"); min_score (0.6)
//   FaceEmbedderNode    in (FaceList) -> out (FaceList): 128 numbers per face
//   FaceIdentifierNode  in (FaceList) -> out (FaceList): names from the people gallery
//       database ("": the user's data dir, core/data's default), threshold (0.22)
//   FaceLogger          in (FaceList): one log line per frame with faces (names, boxes)
//   ObjectDetectorNode  in (VideoFrame) -> out (ObjectList): COCO objects (NanoDet, see
//       object_detector.h); min_score (0.35), nms_iou (0.5); model ("": find_model)
//   ObjectLogger        in (ObjectList): one log line per frame with objects (labels, boxes)
//
// The nodes live in the static library marvin_vision: call register_vision_nodes() once
// before building a graph that uses them.
#ifndef MARVIN_VISION_VISION_NODES_H_
#define MARVIN_VISION_VISION_NODES_H_

#include "graph/node_registry.h"
#include "graph/packet.h"
#include "vision/camera.h"
#include "vision/face.h"
#include "vision/object_detector.h"

MARVIN_PACKET_TYPE(marvin::vision::Frame, "VideoFrame");
MARVIN_PACKET_TYPE(marvin::vision::FaceList, "FaceList");
MARVIN_PACKET_TYPE(marvin::vision::ObjectList, "ObjectList");

namespace marvin::vision {

// Adds the node types above to `registry` (the global one by default). Idempotent.
void register_vision_nodes(graph::NodeRegistry& registry = graph::NodeRegistry::global());

}  // namespace marvin::vision

#endif  // MARVIN_VISION_VISION_NODES_H_
