#include "control/find_teacher_mission.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>

#include "control/face_standoff.hpp"
#include "core/frames.hpp"

namespace labo::control {

namespace {
constexpr double kFaceHeightM = 1.6;       // climb to about a standing teacher's face height
constexpr double kFreshObservationS = 0.3;
constexpr double kLostHoldS = 3.0;         // face lost: hold this long, then search again
constexpr double kCoastS = 0.5;            // face lost: keep following its predicted motion this long
// Meeting the teacher in front of the next long leg: wait this long there (in the lab of
// config/lab.json the teacher turns twice, 3 s each, around a 0.5 m leg: 7.25 s), then search.
constexpr double kMeetWaitS = 12.0;
constexpr double kMaxApproachStepM = 0.6;
// Meet this far beyond face_distance_m in front of the next leg's start; the drone comes in to the
// follow distance at kStandoffEaseMps once the teacher walks at it.
constexpr double kMeetBeyondFollowM = 0.2;
// The follow standoff and the meeting points keep this much farther from the walls than the geofence
// (its own margin 0.3 m: the hull touches a wall 0.04 m beyond it) where they can, turned about the
// face: following and meeting run on dead reckoning, and over a bare floor the navdata velocity
// drops out, the estimate stops while the drone drifts on, and the brake comes too late: a meeting
// point a third of a metre from the wall ends in the wall.
constexpr double kWallClearanceM = 0.5;
constexpr double kStandoffEaseMps = 0.2;
// Going round to the meeting point, the drone circles the middle between the corner where the
// teacher stands and the next leg's start (the teacher walks between the two), at the meeting
// point's distance from it (~1.2 m): ~0.85 m from the teacher at least (hull 0.26 m + body 0.25 m
// collide at 0.51 m). Circling the leg's start instead, the chords would cut inside, into a teacher
// standing at the corner. Test "control: going round the teacher keeps to the side inside the fence".
// A teacher walking within this of a corner after which their next long leg heads more than
// kTurnBackRad away from their heading is about to turn round: the drone leaves for the meeting point
// when they reach it.
constexpr double kCornerAheadM = 0.25;
constexpr double kTurnBackRad = 2 * std::numbers::pi / 3;
// Meeting: a face is the teacher on the next leg when it looks within this of the leg's direction (the
// face still turning at the corner would bring the drone back behind them).
constexpr double kOnMeetingLegRad = std::numbers::pi / 3;
// A face found again within this time and distance of the lost one continues the track (its heading
// and velocity): a few lost frames must not reset the heading to where the swaying head looks.
constexpr double kKeepTrackS = 1.0;
constexpr double kKeepTrackM = 0.5;
// Watch points: the teacher stops this far beyond face_distance_m from the camera at a leg's end, so
// the frontal face is inside the detector's ~2.5 m range for the last metre of the leg.
constexpr double kWatchBeyondFollowM = 0.5;
// Hull (0.26 m) + the teacher's body (0.25 m) + margin: nothing is planned closer to the route.
constexpr double kRouteClearanceM = 0.8;
constexpr double kTransitAboveEyesM = 0.6;  // crossing the route: this far above the teacher's eyes
constexpr double kWatchMarginS = 5.0;       // a watch lasts one round of the route plus this
constexpr double kOnLegLateralM = 0.25;     // a face this near a leg's line walks it
constexpr double kSetOffM = 0.2;            // ... once this far past its start (not standing at the corner)
constexpr double kSetOffMps = 0.1;          // ... or moving along it this fast
constexpr double kCornerRadiusM = 0.6;      // a face lost this near a waypoint: the teacher is turning there
constexpr double kMaxOrbitStepRad = std::numbers::pi / 3;  // the standoff's bearing leads the drone's by at most this
constexpr double kMinAimDistanceM = 0.2;   // nearer than this the bearing to the face has no useful rate
constexpr double kRouteRateStepS = 0.1;    // the route's place differenced over this for its velocity
// A teacher met in front of a leg and standing at its start sets off at once at the route's speed.
// Fed forward from the first kSetOffSignM of their walk along the leg in the face's place, or from
// kSetOffLeadS before the route's time (a lead of 0.2 s would start the drone back before the teacher
// sets off); a route's time that the face does not confirm within kSetOffConfirmS was early (the
// teacher still stands). Ends once the face has walked kSetOffM (the track's own velocity has it
// then). Test "control: a teacher met in front of the next leg is followed from their set-off, not
// after the walk shows".
constexpr double kSetOffLeadS = 0.0;
constexpr double kSetOffConfirmS = 0.5;
constexpr double kSetOffSignM = 0.05;
// A face lost for less than this is bridged along the track (no Lost, no meeting).
constexpr double kBriefLossS = 0.25;

double bearing(const Eigen::Vector3d& from, const Eigen::Vector3d& to) { return std::atan2(to.y() - from.y(), to.x() - from.x()); }

// Does the straight flight from a to b pass within `clearance` of the teacher's route (floor plane)?
bool crosses_route(const Eigen::Vector3d& a, const Eigen::Vector3d& b, const fusion::TeacherRoute& route, double clearance) {
  const int samples = 1 + static_cast<int>((b - a).head<2>().norm() / 0.05);
  for (int k = 0; k <= samples; ++k)
    if (distance_to_route((a + (b - a) * (static_cast<double>(k) / samples)).head<2>(), route) < clearance) return true;
  return false;
}
}  // namespace

int FindTeacherMission::stage_index() const {
  switch (step_) {
    case Step::Init: return 1;
    case Step::Sweep:
    case Step::Reposition:
    case Step::Watch: return 2;
    default: return 3;
  }
}

std::string FindTeacherMission::describe(Seconds t) const {
  switch (step_) {
    case Step::Init: return "1 " + init_.describe();
    case Step::Sweep: return "2 search: yaw sweep at viewpoint " + std::to_string(viewpoint_ + 1);
    case Step::Reposition: return "2 search: moving to viewpoint " + std::to_string(viewpoint_ + 1);
    case Step::Watch:
      return "2 search: watching the teacher's route at viewpoint " + std::to_string(viewpoint_ + 1) + " (" +
             format_seconds(t - since_) + " s)";
    case Step::Follow: return "3 face-follow";
    case Step::Lost: return "3 face-follow: face lost, holding (" + format_seconds(t - since_) + " s)";
    case Step::Meet: return "3 face-follow: meeting the teacher in front of their next leg (" + format_seconds(t - since_) + " s)";
    case Step::Done: return "done: " + result_;
  }
  return "";
}

bool FindTeacherMission::face_seen(const MissionContext& ctx) const {
  const fusion::TargetObservation f = ctx.perception.face();
  return f.state == fusion::TrackState::Tracking && ctx.t - f.t < kFreshObservationS;
}

std::vector<Eigen::Vector3d> FindTeacherMission::viewpoints(const MissionContext& ctx) const {
  const Eigen::Vector3d lo = ctx.autopilot.fence().min(), hi = ctx.autopilot.fence().max();
  const Eigen::Vector3d c = 0.5 * (lo + hi);
  const Eigen::Vector3d q = 0.25 * (hi - lo);
  return {{c.x(), c.y(), kFaceHeightM},
          {c.x() + q.x(), c.y() + q.y(), kFaceHeightM},
          {c.x() - q.x(), c.y() + q.y(), kFaceHeightM},
          {c.x() - q.x(), c.y() - q.y(), kFaceHeightM},
          {c.x() + q.x(), c.y() - q.y(), kFaceHeightM}};
}

void FindTeacherMission::plan_transit(const MissionContext& ctx, const WatchPoint& to) {
  const Eigen::Vector3d here = ctx.pose.T_world_body.translation();
  const double yaw = ypr_from_rotation(ctx.pose.T_world_body.linear())[0];
  transit_.clear();
  transit_leg_ = 0;
  if (crosses_route(here, to.position, ctx.lab.teacher, kRouteClearanceM)) {
    // Over the teacher's head, not through them.
    const double high = std::min(ctx.lab.teacher.eye_height_m + kTransitAboveEyesM, ctx.autopilot.fence().max().z());
    transit_.push_back({{here.x(), here.y(), high}, yaw});
    transit_.push_back({{to.position.x(), to.position.y(), high}, to.yaw});
  }
  transit_.push_back({to.position, to.yaw});
}

Geofence FindTeacherMission::roomy_fence(const MissionContext& ctx) const {
  const Geofence& fence = ctx.autopilot.fence();
  // A small room keeps what room it has (the margin never more than half its narrowest extent).
  const double margin = std::min(kWallClearanceM, 0.45 * (fence.max() - fence.min()).minCoeff());
  return Geofence(fence.min(), fence.max(), std::max(margin, 0.0));
}

bool FindTeacherMission::predict_from_route(const MissionContext& ctx, double corner_radius_m) {
  if (watch_points_.empty()) return false;
  // The next long leg, on the route itself: the meeting point drawn in from the walls is where the
  // drone waits, not where the teacher walks (drawn in 0.2 m from leg A of config/lab.json, the leg's
  // start lies within the corner radius of the short leg's too, and the prediction would take that
  // 0.5 m leg's length: the predicted teacher would stop 0.5 m into leg A while the real one walks on
  // at the drone). Tests "control: next_long_leg is the route's own leg, not one drawn in from the
  // walls" and "control: a face lost as the teacher sets off along the leg by the wall is predicted
  // along the whole leg".
  return predict_from_route(ctx, next_long_leg(ctx.lab.teacher, track_.position().head<2>(), corner_radius_m));
}

bool FindTeacherMission::predict_walk_along_leg(const MissionContext& ctx) {
  // A face lost in the middle of a leg while the teacher walks it (the head's sway takes it past the
  // detector's ~30°): by the route they walk on into its end and turn there, so the drone keeps
  // backing off ahead of them at the route's speed and then meets them as at a corner. Holding
  // instead, the drone would be walked into, or the track, moved by the estimate's corrections, would
  // reach the corner and be taken for a teacher standing there for an unknown time (the meeting then
  // walks the next leg at once and the drone waits at its far end, metres away). Test "control: a face
  // lost in the middle of a leg is followed on along the route, not held".
  if (watch_points_.empty() || !track_.walking()) return false;
  const std::optional<std::size_t> corner = waypoint_walked_into(
      ctx.lab.teacher, track_.position().head<2>(), track_.velocity().head<2>(), kOnLegLateralM, kSetOffMps);
  return corner && predict_from_route(ctx, next_long_leg_from(ctx.lab.teacher, *corner));
}

bool FindTeacherMission::predict_from_route(const MissionContext& ctx, const std::optional<RouteLeg>& leg) {
  if (watch_points_.empty() || !leg) return false;
  const Eigen::Vector2d corner = ctx.lab.teacher.waypoints[leg->corner];
  meet_centre_ = Eigen::Vector3d(0.5 * (corner.x() + leg->from.x()), 0.5 * (corner.y() + leg->from.y()), track_.position().z());
  // When they set off along it. Two ways to get it wrong: holding at the leg's start while the
  // teacher, lost just after setting off, walks into the drone (test "control: a face lost as the
  // teacher sets off along the leg by the wall is predicted along the whole leg"); or, with the
  // teacher lost as they reach a corner, walking the next leg at once and waiting far ahead of a
  // teacher who still stands there (test "control: a face lost at a corner waits for the teacher
  // pausing there, not ahead of them"). So:
  //  - walking along the leg already (past its start, or moving along it): from when last seen;
  //  - walked into the corner from the leg before (a sustained spell of walking, not along this leg,
  //    ended less than a pause ago): after the route's pauses and short legs from where it ended;
  //  - standing at the corner, for how long is not known: any moment, so from when last seen (the
  //    drone backs off ahead of them; a teacher still standing is found again walking at it).
  // On the leg already means on its line (a leg walked the other way before a turn back lies
  // alongside it, 0.5 m off in the lab, and is no part of it).
  const Eigen::Vector2d xy = track_.position().head<2>();
  const Eigen::Vector2d from_start = xy - leg->from;
  const double lateral = std::abs(leg->along.x() * from_start.y() - leg->along.y() * from_start.x());
  const double on_leg = lateral < kOnLegLateralM ? from_start.dot(leg->along) : -1.0;
  const Eigen::Vector2d v = track_.velocity().head<2>();
  // The velocity an unconfirmed set-off feed-forward gave the track is an expectation, not a walk seen:
  // it is no sign of one (taken for a teacher walking the leg, the meeting would back off along it at
  // once while they still stand; test "control: a face that moves a few cm along the next leg and is
  // lost is no set-off for the meeting"). And a velocity counts only with the face's place on the leg:
  // a head turning at the corner moves the face along it too, by up to its ~0.1 m from the turning
  // axis, far enough to start and confirm a feed-forward; a teacher who has set off is on it (test
  // "control: a head turning at the corner, its face not yet on the next leg, is no set-off when lost").
  const bool velocity_seen = !(set_off_unconfirmed() && leg->index == meet_leg_.index);
  const bool set_off = on_leg > kSetOffM || (velocity_seen && on_leg > 0.0 && v.dot(leg->along) > kSetOffMps);
  const Seconds seen_at = last_face_t_ >= 0 ? last_face_t_ : ctx.t;
  const TeacherTrack::WalkSpell& walked = track_.last_walk();
  const bool walked_in = !set_off && walked.seen && seen_at - walked.to < ctx.lab.teacher.pause_s &&
                         walked.direction.dot(leg->along) < std::cos(kOnMeetingLegRad);
  // Seen on the leg into the corner, short of it: walking in, however briefly the face was seen (a
  // glimpse at the end of a leg, too short for a sustained spell, would otherwise be a teacher standing
  // at the corner, and the next long leg walked at once, seconds early). Test "control: a face first
  // seen for a moment at the end of a leg waits out the short leg before the next long one".
  const double short_of_corner = metres_short_of_waypoint(ctx.lab.teacher, xy, leg->corner, kOnLegLateralM);
  const bool seen_walking_in = !set_off && !walked_in && short_of_corner > kSetOffM;
  const bool arriving = walked_in || seen_walking_in;
  // Where and when they were last seen walking in: the rest of the way is timed from that place at that
  // time. (The place last seen may be later and nearer the corner: timed from the end of the walk, the
  // way walked since would be counted twice, the set-off predicted early, and the drone would back off
  // ahead of a teacher still standing. Test "control: a face lost walking into a corner and seen again
  // on the way times the set-off from the walk seen".)
  const Seconds walked_to = walked_in ? walked.to : seen_at;
  const Eigen::Vector2d walked_from_xy = walked_in ? walked.at : xy;
  // A meeting on this leg already expected them later (the face then taken up at the corner for too
  // short a time to see them walk in): that still holds. Test "control: a face taken up for a moment at
  // the corner keeps the meeting's wait for the teacher to set off".
  const bool expected_later = meet_leg_.index == leg->index && meet_walk_from_ > seen_at && meet_walk_from_ < ctx.t + kMeetWaitS;
  Seconds walk_from = seen_at, arrived_at = -1;
  if (arriving) {
    walk_from = walked_to + seconds_to_set_off(ctx.lab.teacher, walked_from_xy, *leg);
    arrived_at = walked_to + (corner - walked_from_xy).norm() / std::max(ctx.lab.teacher.speed_mps, 0.1);
  } else if (!set_off && expected_later) {
    walk_from = meet_walk_from_;
    arrived_at = meet_arrived_at_;
  }
  meet_leg_ = *leg;
  meet_on_leg_m_ = set_off ? std::clamp(on_leg, 0.0, leg->length_m) : 0.0;
  meet_walk_from_ = walk_from;
  meet_arrived_at_ = arrived_at;
  // Walking into the corner still: followed there first (leaving at once, the drone would swing off a
  // teacher with up to 0.6 m still to walk towards it).
  walk_in_from_ = walked_from_xy;
  walk_in_t0_ = walked_to;
  walk_in_until_ = arriving ? arrived_at : -1.0;
  track_.place(leg->from + meet_on_leg_m_ * leg->along, std::atan2(leg->along.y(), leg->along.x()));
  standoff_m_ = ctx.config.mission.face_distance_m + kMeetBeyondFollowM;
  return true;
}

void FindTeacherMission::place_on_meeting_leg(const MissionContext& ctx) {
  const double speed = std::max(ctx.lab.teacher.speed_mps, 0.1);
  const bool may_walk = ctx.t > meet_walk_from_;
  const double walked = meet_on_leg_m_ + (may_walk ? speed * (ctx.t - meet_walk_from_) : 0.0);
  const bool walking = may_walk && walked < meet_leg_.length_m;
  track_.place(meet_leg_.from + std::min(walked, meet_leg_.length_m) * meet_leg_.along,
               std::atan2(meet_leg_.along.y(), meet_leg_.along.x()),
               walking ? Eigen::Vector2d(speed * meet_leg_.along) : Eigen::Vector2d::Zero());
}

bool FindTeacherMission::walk_into_corner(MissionContext& ctx) {
  if (ctx.t >= walk_in_until_) return false;
  const Eigen::Vector2d corner = ctx.lab.teacher.waypoints[meet_leg_.corner];
  const Eigen::Vector2d to = corner - walk_in_from_;
  if (to.norm() < 1e-6) return false;
  const Eigen::Vector2d dir = to.normalized();
  const double speed = std::max(ctx.lab.teacher.speed_mps, 0.1);
  track_.place(walk_in_from_ + std::min(to.norm(), speed * (ctx.t - walk_in_t0_)) * dir, std::atan2(dir.y(), dir.x()),
               speed * dir);
  const double meeting_standoff = standoff_m_;
  standoff_m_ = ctx.config.mission.face_distance_m;
  fly_standoff(ctx, false, track_.position());
  standoff_m_ = meeting_standoff;
  return true;
}

bool FindTeacherMission::turning_back_ahead(const MissionContext& ctx) {
  if (watch_points_.empty()) return false;
  const std::optional<RouteLeg> next = next_long_leg(ctx.lab.teacher, track_.position().head<2>(), kCornerAheadM);
  if (!next || std::abs(wrap_angle(std::atan2(next->along.y(), next->along.x()) - track_.heading())) <= kTurnBackRad) {
    corner_eta_ = -1;
    return false;
  }
  // Only once they reach it: the walk into the corner is followed to its end. Leaving 0.25 m before
  // it, the drone would swing off a teacher still walking for about a second (the face's place,
  // measured a little short, runs ahead of them), too near and with the face off the centre ray, and
  // those ticks count in the follow's error. The pause (3 s) and the short leg after it leave the time
  // to go round. When they reach it is timed from where the track came within kCornerAheadM at the
  // route's speed: the track's speed does not say when they stop (the face's jitter reads as
  // 0.2-0.35 m/s standing, in the model at 1.3 m).
  if (corner_eta_ < 0) {
    const Eigen::Vector2d corner = ctx.lab.teacher.waypoints[next->corner];
    corner_eta_ = ctx.t + (corner - track_.position().head<2>()).norm() / std::max(ctx.lab.teacher.speed_mps, 0.1);
  }
  return ctx.t >= corner_eta_;
}

bool FindTeacherMission::face_on_meeting_leg(const MissionContext& ctx) const {
  if (!face_seen(ctx)) return false;
  // Only once in front of the leg: a face seen from the side while going round is followed from there.
  const Eigen::Vector2d out = (ctx.pose.T_world_body.translation() - meet_centre_).head<2>();
  if (std::abs(wrap_angle(std::atan2(out.y(), out.x()) - track_.heading())) > kOnMeetingLegRad) return false;
  const double looking = facing_heading(world_pose_of(ctx.perception.face(), ctx.pose, CameraId::Front));
  return std::abs(wrap_angle(looking - track_.heading())) < kOnMeetingLegRad;
}

void FindTeacherMission::start_search(MissionContext& ctx) {
  search_started_ = ctx.t;
  watch_points_ = teacher_watch_points(ctx.lab.teacher, ctx.autopilot.fence(),
                                       ctx.config.mission.face_distance_m + kWatchBeyondFollowM, kRouteClearanceM);
  if (watch_points_.empty()) {
    enter(Step::Sweep, ctx.t);
    return;
  }
  // The nearest watch point first.
  const Eigen::Vector3d here = ctx.pose.T_world_body.translation();
  viewpoint_ = 0;
  for (std::size_t i = 1; i < watch_points_.size(); ++i)
    if ((watch_points_[i].position - here).norm() < (watch_points_[viewpoint_].position - here).norm()) viewpoint_ = i;
  watch_ = watch_points_[viewpoint_];
  plan_transit(ctx, watch_);
  enter(Step::Reposition, ctx.t);
}

void FindTeacherMission::follow(MissionContext& ctx) {
  const fusion::TargetObservation f = ctx.perception.face();
  if (f.t == last_face_t_ && !fresh_) return;  // no new face result: keep the moving set point
  const Eigen::Isometry3d T_world_face = world_pose_of(f, ctx.pose, CameraId::Front);
  const double d = ctx.config.mission.face_distance_m;
  if (fresh_ && !resume_track_) standoff_m_ = d;
  const bool continues = last_face_t_ >= 0 && f.t - last_face_t_ < kKeepTrackS &&
                         (T_world_face.translation() - track_.position()).head<2>().norm() < kKeepTrackM;
  if (resume_track_) track_.resume(T_world_face, f.t);
  else if (fresh_ && !continues) track_.reset(T_world_face, f.t);
  else track_.update(T_world_face, f.t);
  resume_track_ = false;
  expect_set_off(ctx);
  // Met in front of a leg, the drone waits farther out; it comes in to the follow distance only as
  // the teacher walks at it: from the follow distance the drone's lag (the walk noticed, then the
  // drone accelerated backwards) would let the teacher come within 0.55 m.
  // (Per face result, not over a gap: after a meeting the last face was seconds ago, and the whole
  // 0.2 m would come at once.)
  if (standoff_m_ > d && track_.walking())
    standoff_m_ = std::max(d, standoff_m_ - kStandoffEaseMps * std::min(f.t - last_face_t_, kFreshObservationS));
  last_face_t_ = f.t;
  fly_standoff(ctx, fresh_, track_.position());
  fresh_ = false;
}

void FindTeacherMission::expect_set_off(const MissionContext& ctx) {
  // After a meeting the teacher stands at the corner until the route's set-off time and then walks at
  // once at the route's speed; seen through the face alone, the walk shows only after the velocity's
  // low-pass (~0.4 s) and the perception delay, and the teacher would come too close in the first
  // seconds of the leg. Test "control: a teacher met in front of the next leg is followed from their
  // set-off, not after the walk shows".
  if (!set_off_armed_) return;
  const Eigen::Vector2d xy = track_.position().head<2>();
  if (!set_off_from_known_) {
    set_off_from_ = xy;
    set_off_from_known_ = true;
  }
  const double walked = (xy - set_off_from_).dot(meet_leg_.along);
  if (walked > kSetOffM || ctx.t > set_off_armed_until_) {
    set_off_armed_ = false;
    return;
  }
  const bool seen_walking = walked > kSetOffSignM;
  if (set_off_started_ < 0 && (seen_walking || (set_off_timed_ && ctx.t >= meet_walk_from_ - kSetOffLeadS))) {
    set_off_started_ = ctx.t;
    set_off_by_route_ = !seen_walking;
    set_off_walked_at_start_ = walked;
  }
  if (set_off_started_ < 0) return;
  // Confirmed only by the walk going on: the face's place moving another kSetOffSignM along the leg
  // since the feed-forward started. A face that moved 5 cm and stopped is a head turning at the corner
  // (the face sits ~0.1 m in front of the turning axis) or the pose's jitter, not a walk. Test
  // "control: a face that moves a few cm along the next leg and stops is no set-off while followed".
  if (walked - set_off_walked_at_start_ >= kSetOffSignM) set_off_confirmed_ = true;
  if (!set_off_confirmed_ && ctx.t - set_off_started_ > kSetOffConfirmS) {
    // Early: they still stand. A route's time is not used again; the next sign is measured from here.
    if (set_off_by_route_) set_off_timed_ = false;
    set_off_from_ = xy;
    set_off_started_ = -1;
    track_.stand();
    return;
  }
  track_.expect_walk(std::max(ctx.lab.teacher.speed_mps, 0.1) * meet_leg_.along);
}

void FindTeacherMission::fly_standoff(MissionContext& ctx, bool new_waypoint, const Eigen::Vector3d& orbit_centre) {
  fly_standoff(ctx, new_waypoint, orbit_centre, track_.position(), track_.velocity());
}

void FindTeacherMission::fly_standoff(MissionContext& ctx, bool new_waypoint, const Eigen::Vector3d& orbit_centre,
                                      const Eigen::Vector3d& look_at, const Eigen::Vector3d& look_at_velocity) {
  const double d = standoff_m_;
  const Eigen::Vector3d here = ctx.pose.T_world_body.translation();
  const double a = track_.heading();
  PoseTarget next = follow_standoff(standoff_target(track_.T_world_upright_face(a), d, ctx.centre_ray_front),
                                    orbit_centre, here, roomy_fence(ctx), kMaxOrbitStepRad);
  if (!ctx.autopilot.fence().contains(next.position)) next.position = ctx.autopilot.fence().clamp(next.position);
  // Feed-forward: the standoff moves with the teacher and swings round them as they turn.
  next.velocity = track_.velocity() + d * track_.heading_rate() * Eigen::Vector3d(-std::sin(a), std::cos(a), 0.0);
  // Point the camera at the face from where the drone is (the same as the line of sight once in
  // place; it keeps a walking teacher in view while the drone catches up), with the face on the ray
  // through the image centre rather than the principal point.
  next.yaw = wrap_angle(bearing(here, look_at) + std::atan(ctx.centre_ray_front.x()));
  // ... and turn with that bearing as the drone and the face move, fed forward: going round the
  // teacher to a meeting point at ~0.5 rad/s, the yaw loop alone lags 0.15-0.3 rad, a quarter of a
  // metre off the centre ray at 0.9 m. Test "control: going round to the next leg, the camera turns
  // with the bearing to the teacher on the short leg".
  const Eigen::Vector2d r = (look_at - here).head<2>();
  const Eigen::Vector2d v = (look_at_velocity - ctx.pose.velocity_world).head<2>();
  if (r.norm() > kMinAimDistanceM) next.yaw_rate = (r.x() * v.y() - r.y() * v.x()) / r.squaredNorm();
  // A far standoff (the face found from 2-4 m, the teacher walking at the drone) is approached
  // through a set point at most kMaxApproachStepM ahead: a full jump saturates the tilt and the drone
  // overshoots into the teacher's face.
  const Eigen::Vector3d to_standoff = next.position - here;
  if (to_standoff.norm() > kMaxApproachStepM) next.position = here + kMaxApproachStepM * to_standoff.normalized();
  ctx.autopilot.go_to(next, ctx.t, new_waypoint);
}

void FindTeacherMission::lost(MissionContext& ctx) {
  const Seconds lost_for = ctx.t - since_;
  const bool just_lost = fresh_;
  fresh_ = false;
  if (just_lost && (predict_from_route(ctx, kCornerRadiusM) || predict_walk_along_leg(ctx))) {
    // Lost at a corner of a known route: the route says where they go, at once. Coasting first along
    // the track's lagging velocity (0.2 m/s, a teacher 0.3 s into a leg walking at 0.4 m/s) would keep
    // the drone closing on them. Test "control: a face lost at a corner: the drone waiting on the next
    // leg keeps ahead of a teacher who sets off unseen".
    enter(Step::Meet, ctx.t);
    return;
  }
  if (lost_for < kCoastS) {
    // Coast along the teacher's last motion and turn (they most likely walked or turned out of view).
    track_.coast(ctx.t - last_tick_);
    fly_standoff(ctx, false, track_.position());
  } else if (predict_from_route(ctx, kCornerRadiusM)) {
    enter(Step::Meet, ctx.t);  // lost at a corner: they are turning onto the next leg
    return;
  } else if (auto target = ctx.autopilot.target()) {
    // Hold the place, keep looking where the face went.
    const Eigen::Vector3d to_face = track_.position() - ctx.pose.T_world_body.translation();
    ctx.autopilot.go_to({target->position, std::atan2(to_face.y(), to_face.x())}, ctx.t, false);
  }
  if (face_seen(ctx)) enter(Step::Follow, ctx.t);
  else if (lost_for > kLostHoldS) start_search(ctx);
}

void FindTeacherMission::meet(MissionContext& ctx) {
  fresh_ = false;
  if (walk_into_corner(ctx)) {
    // Still in front of them: a face found again is followed on.
    if (face_seen(ctx)) enter(Step::Follow, ctx.t);
    return;
  }
  place_on_meeting_leg(ctx);
  // Round the middle between the corner and the leg's start, then in to the meeting point, the camera
  // on where the route has them meanwhile (pausing, walking the short leg: looking at the leg's start
  // instead would put their face 0.3-0.5 rad off the centre ray on the short leg, in the model).
  Eigen::Vector3d look_at = track_.position();
  Eigen::Vector3d look_at_velocity = track_.velocity();
  if (meet_arrived_at_ >= 0 && ctx.t < meet_walk_from_) {
    const double since_arrival = ctx.t - meet_arrived_at_;
    look_at.head<2>() = route_place_before(ctx.lab.teacher, meet_leg_, since_arrival);
    const Eigen::Vector2d ahead = route_place_before(ctx.lab.teacher, meet_leg_, since_arrival + kRouteRateStepS);
    look_at_velocity = Eigen::Vector3d::Zero();
    look_at_velocity.head<2>() = (ahead - look_at.head<2>()) / kRouteRateStepS;
  }
  fly_standoff(ctx, false, meet_centre_, look_at, look_at_velocity);
  if (face_on_meeting_leg(ctx)) {
    resume_track_ = true;
    // Standing at the leg's start; the set-off is timed only for a teacher seen walking into the
    // corner (else it is "any moment"), and only while that time is still ahead: a face taken up
    // standing there after it shows the time was early (fed forward at once, the drone would back off
    // too far from a teacher who still stands).
    set_off_armed_ = meet_on_leg_m_ <= 0;
    set_off_timed_ = meet_arrived_at_ >= 0 && ctx.t < meet_walk_from_;
    set_off_from_known_ = false;
    set_off_started_ = -1;
    set_off_confirmed_ = false;
    set_off_armed_until_ = std::max(ctx.t, meet_walk_from_) + kMeetWaitS;
    enter(Step::Follow, ctx.t);
  } else if (ctx.t - since_ > kMeetWaitS) {
    start_search(ctx);
  }
}

void FindTeacherMission::follow_estimate_corrections(const MissionContext& ctx) {
  // Faces are placed in the world from the drone's pose estimate, so when the estimator corrects that
  // estimate (on dead reckoning over a bare floor the velocity-dropout handling moves it by a tenth of
  // a metre within one tick), every face after it is placed that much farther: differenced into the
  // track's velocity, a 0.12 m correction reads as 0.27 m/s of walking: a teacher standing at a corner
  // would seem to walk and their heading be let go, a walking teacher's heading would swing and the
  // set point with it. The part of the estimate's displacement that its velocity does not explain
  // moves the track with it. Test "control: a correction of the drone's pose estimate is not taken for
  // the teacher's walk".
  const Eigen::Vector3d p = ctx.pose.T_world_body.translation();
  if (!ctx.pose.valid) {
    have_last_pose_ = false;
    return;
  }
  if (have_last_pose_ && ctx.t > last_tick_)
    track_.shift(p - last_position_ - 0.5 * (last_velocity_ + ctx.pose.velocity_world) * (ctx.t - last_tick_));
  have_last_pose_ = true;
  last_position_ = p;
  last_velocity_ = ctx.pose.velocity_world;
}

MissionOutcome FindTeacherMission::step(MissionContext& ctx) {
  const auto& m = ctx.config.mission;
  follow_estimate_corrections(ctx);
  const Eigen::Vector3d here = ctx.pose.T_world_body.translation();
  const double yaw = ypr_from_rotation(ctx.pose.T_world_body.linear())[0];
  ctx.camera = CameraId::Front;
  ctx.focus.instrument_id.clear();
  ctx.focus.platform = false;
  ctx.focus.face = true;
  if (stop_requested_ && step_ != Step::Done) {
    ctx.autopilot.hold_here(ctx.pose, ctx.t);
    result_ = "face-follow stopped on request";
    enter(Step::Done, ctx.t);
  }
  switch (step_) {
    case Step::Init:
      // Climb to about a standing teacher's face height; SLAM gets its scale before the search.
      if (init_.step(ctx, ctx.lab.teacher.waypoints.empty() ? kFaceHeightM : ctx.lab.teacher.eye_height_m)) start_search(ctx);
      break;
    case Step::Sweep: {
      if (fresh_) sweep_start_yaw_ = ctx.autopilot.target() ? ctx.autopilot.target()->yaw : yaw;
      const double swept = m.face_search_yaw_rate * (ctx.t - since_);
      const Eigen::Vector3d hold = ctx.autopilot.target() ? ctx.autopilot.target()->position : here;
      ctx.autopilot.go_to({hold, sweep_start_yaw_ + swept}, ctx.t, fresh_);
      fresh_ = false;
      if (face_seen(ctx)) enter(Step::Follow, ctx.t);
      else if (swept >= 2 * std::numbers::pi) {
        viewpoint_ = (viewpoint_ + 1) % viewpoints(ctx).size();
        enter(Step::Reposition, ctx.t);
      }
      break;
    }
    case Step::Reposition:
      if (watch_points_.empty()) {
        if (fresh_) ctx.autopilot.go_to({viewpoints(ctx)[viewpoint_], yaw}, ctx.t);
        fresh_ = false;
        if (face_seen(ctx)) enter(Step::Follow, ctx.t);
        else if (ctx.autopilot.reached() || ctx.t - since_ > 15.0) enter(Step::Sweep, ctx.t);
        break;
      }
      if (fresh_) ctx.autopilot.go_to(transit_[transit_leg_], ctx.t);
      fresh_ = false;
      if (face_seen(ctx)) {
        enter(Step::Follow, ctx.t);
      } else if (ctx.autopilot.reached() || ctx.t - since_ > 15.0) {
        if (++transit_leg_ < transit_.size()) enter(Step::Reposition, ctx.t);
        else enter(Step::Watch, ctx.t);
      }
      break;
    case Step::Watch:
      // Hold at the watch point, facing the oncoming teacher, for one round of the route.
      if (fresh_) ctx.autopilot.go_to({watch_.position, watch_.yaw}, ctx.t, false);
      fresh_ = false;
      if (face_seen(ctx)) {
        enter(Step::Follow, ctx.t);
      } else if (ctx.t - since_ > ctx.lab.teacher.cycle_s() + kWatchMarginS) {
        viewpoint_ = (viewpoint_ + 1) % watch_points_.size();
        watch_ = watch_points_[viewpoint_];
        plan_transit(ctx, watch_);
        enter(Step::Reposition, ctx.t);
      }
      break;
    case Step::Follow:
      if (!face_seen(ctx)) {
        // A face lost for a frame or a few (at the tracker's limit, ~35 degrees of head yaw, it
        // flickers: tracked, lost, tracked every other frame) is bridged along the track: each
        // flicker would send the mission through Lost and a meeting and back, reset the controller and
        // let the set point jump. Test "control: a face lost for a few frames mid-leg is bridged along
        // the track, not taken for a loss".
        // Not near a corner of a known route: a face lost there is a teacher turning away, and the
        // route says at once where they go.
        if (last_face_t_ >= 0 && ctx.t - last_face_t_ < kBriefLossS && track_.walking() &&
            !next_long_leg(ctx.lab.teacher, track_.position().head<2>(), kCornerRadiusM)) {
          // The set point flies the coasted place; the track itself stays where the face was last
          // seen, when: coasted, it would reach a corner's radius and a teacher still walking into it
          // be taken for one standing there, whose set-off is "any moment" (the meeting would then
          // leave ahead of them early).
          const TeacherTrack seen = track_;
          track_.coast(ctx.t - last_face_t_);
          fly_standoff(ctx, false, track_.position());
          track_ = seen;
          break;
        }
        enter(Step::Lost, ctx.t);
        break;
      }
      follow(ctx);
      if (turning_back_ahead(ctx) && predict_from_route(ctx, kCornerAheadM)) enter(Step::Meet, ctx.t);
      break;
    case Step::Lost:
      lost(ctx);
      break;
    case Step::Meet:
      meet(ctx);
      break;
    case Step::Done:
      ctx.focus.face = false;
      break;
  }
  const bool searching = step_ == Step::Sweep || step_ == Step::Reposition || step_ == Step::Watch;
  if (searching && ctx.t - search_started_ > m.face_search_timeout_s) {
    result_ = "no face found in " + format_seconds(m.face_search_timeout_s) + " s";
    ctx.autopilot.hold_here(ctx.pose, ctx.t);
    stage_text_ = "failed: " + result_;
    return MissionOutcome::Failed;
  }
  stage_text_ = describe(ctx.t);
  last_tick_ = ctx.t;
  return step_ == Step::Done ? MissionOutcome::Succeeded : MissionOutcome::Running;
}

MissionOutcome ReturnHomeMission::step(MissionContext& ctx) {
  const HomeLanding::Step s = home_.step(ctx);
  stage_text_ = home_.describe(ctx.t);
  if (s == HomeLanding::Step::Failed) {
    result_ = home_.failure();
    return MissionOutcome::Failed;
  }
  if (s != HomeLanding::Step::Landed) return MissionOutcome::Running;
  result_ = "returned home (" + why_ + ") and landed" + (home_.failure().empty() ? " on the platform" : ": " + home_.failure());
  return MissionOutcome::Succeeded;
}

}  // namespace labo::control
