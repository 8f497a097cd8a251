#pragma once
// A test double's vision job: the frame, copied, for one instrument front-end. Tests only.
#include "localization/fusion/vision_job.hpp"

namespace labo::test {

inline bool instrument_job(const VideoFrame& frame, fusion::TargetFrontEnd& front_end, fusion::VisionJob& job) {
  job.clear();
  job.t = frame.t;
  frame.bgr.copyTo(job.gray);
  job.instrument = &front_end;
  job.instrument_id = "oscilloscope";
  return true;
}

}  // namespace labo::test
