#include "framing/frame_classifier.hpp"

#include <cassert>

#include "core/crc16.hpp"
#include "framing/frame_shape.hpp"

namespace rtu {

void classify_frame(Record& frame, bool crc_known_valid) {
  const auto bytes = frame.bytes();
  const std::size_t length = bytes.size();
  assert(!crc_known_valid || crc16_valid(bytes));
  frame.crc_ok = crc_known_valid || crc16_valid(bytes);
  if (!frame.crc_ok) frame.issues.add(IssueId::kCrc);

  // A frame is truncated when it is shorter than every length its start predicts.
  bool any_prediction = false;
  bool all_longer = true;
  frame.shape_fit = kFitsNone;
  for (const Role role : {Role::kRequest, Role::kResponse}) {
    const Shape shape = predict_shape(bytes, role);
    switch (shape.status) {
      case ShapeStatus::kLength:
        any_prediction = true;
        if (shape.value == length) {
          frame.shape_fit |= role == Role::kRequest ? kFitsRequest : kFitsResponse;
        }
        if (shape.value <= length) all_longer = false;
        break;
      case ShapeStatus::kNeedMore: any_prediction = true; break;
      case ShapeStatus::kUnpredictable: all_longer = false; break;
      case ShapeStatus::kImpossible: break;
    }
  }
  if (!frame.crc_ok && any_prediction && all_longer) frame.issues.add(IssueId::kTruncated);
}

}  // namespace rtu
