#pragma once
// SourceSelector: which vision source drives the estimate, with hysteresis. A source becomes
// established after `enter_count` consecutive consistent frames and stays so until `timeout` passes
// without one; among established sources the homography (close to an instrument, the most precise)
// beats the face, which beats SLAM; with none, dead reckoning. The colour follows the paper's code.
#include <array>

#include "core/time.hpp"
#include "localization/estimation/observations.hpp"

namespace labo::estimation {

class SourceSelector {
 public:
  SourceSelector(int enter_count, Seconds timeout) : enter_count_(enter_count), timeout_(timeout) {}

  // A frame of `source` passed the consistency checks at t (quality 0..1).
  void on_consistent(LocalizationSource source, Seconds t, double quality);
  // A frame was rejected (jump, not tracking): the run of consecutive frames starts over.
  void on_inconsistent(LocalizationSource source);
  // The source's frames were fused into the estimate at t.
  void on_fused(LocalizationSource source, Seconds t);
  void reset();

  int consecutive(LocalizationSource source) const { return track(source).consecutive; }
  bool established(LocalizationSource source, Seconds t) const;
  // Fused within the timeout (for the navdata noise: vision is holding the estimate).
  bool any_fused_recently(Seconds t) const;
  LocalizationSource active(Seconds t) const;
  SourceColour colour(Seconds t) const;
  double quality(Seconds t) const;

 private:
  struct Track {
    int consecutive = 0;
    Seconds last_consistent = -1e9;
    Seconds last_fused = -1e9;
    double quality = 0;
  };
  const Track& track(LocalizationSource s) const { return tracks_[static_cast<int>(s)]; }
  Track& track(LocalizationSource s) { return tracks_[static_cast<int>(s)]; }

  int enter_count_;
  Seconds timeout_;
  std::array<Track, 3> tracks_{};  // Slam, Homography, Face
  LocalizationSource last_vision_ = LocalizationSource::Slam;
};

}  // namespace labo::estimation
