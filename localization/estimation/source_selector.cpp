#include "localization/estimation/source_selector.hpp"

namespace labo::estimation {

void SourceSelector::on_consistent(LocalizationSource source, Seconds t, double quality) {
  if (source == LocalizationSource::DeadReckoning) return;
  Track& tr = track(source);
  if (t - tr.last_consistent > timeout_) tr.consecutive = 0;  // a gap breaks the run
  ++tr.consecutive;
  tr.last_consistent = t;
  tr.quality = quality;
  if (established(source, t) && active(t) == source) last_vision_ = source;
}

void SourceSelector::on_inconsistent(LocalizationSource source) {
  if (source == LocalizationSource::DeadReckoning) return;
  track(source).consecutive = 0;
}

void SourceSelector::on_fused(LocalizationSource source, Seconds t) {
  if (source == LocalizationSource::DeadReckoning) return;
  track(source).last_fused = t;
}

void SourceSelector::reset() {
  tracks_ = {};
  last_vision_ = LocalizationSource::Slam;
}

bool SourceSelector::established(LocalizationSource source, Seconds t) const {
  if (source == LocalizationSource::DeadReckoning) return true;
  const Track& tr = track(source);
  return tr.consecutive >= enter_count_ && t - tr.last_consistent <= timeout_;
}

bool SourceSelector::any_fused_recently(Seconds t) const {
  for (const Track& tr : tracks_) {
    if (t - tr.last_fused <= timeout_) return true;
  }
  return false;
}

LocalizationSource SourceSelector::active(Seconds t) const {
  for (LocalizationSource s : {LocalizationSource::Homography, LocalizationSource::Face, LocalizationSource::Slam}) {
    if (established(s, t)) return s;
  }
  return LocalizationSource::DeadReckoning;
}

SourceColour SourceSelector::colour(Seconds t) const {
  switch (active(t)) {
    case LocalizationSource::Slam:
    case LocalizationSource::Face: return SourceColour::Green;
    case LocalizationSource::Homography: return SourceColour::Blue;
    case LocalizationSource::DeadReckoning: break;
  }
  // Vision lost: black after the object's tracking failed, red after SLAM (or the face) was lost.
  return last_vision_ == LocalizationSource::Homography ? SourceColour::Black : SourceColour::Red;
}

double SourceSelector::quality(Seconds t) const {
  const LocalizationSource s = active(t);
  return s == LocalizationSource::DeadReckoning ? 0.0 : track(s).quality;
}

}  // namespace labo::estimation
