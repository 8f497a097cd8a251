#include "drone/ardrone2/navdata_schema.hpp"

#include <array>

namespace labo::ardrone2 {

namespace {

using W = WireType;
// Scales to the units named in si_name.
constexpr double kMilli = 1e-3;

constexpr FieldSpec kDemo[] = {
    {"ctrl_state", W::U32}, {"vbat_flying_percentage", W::U32, 1, "battery_percent", 1.0},
    {"theta", W::F32, 1, "theta_deg", kMilli}, {"phi", W::F32, 1, "phi_deg", kMilli},
    {"psi", W::F32, 1, "psi_deg", kMilli}, {"altitude", W::I32, 1, "altitude_m", kMilli},
    {"vx", W::F32, 1, "vx_mps", kMilli}, {"vy", W::F32, 1, "vy_mps", kMilli}, {"vz", W::F32, 1, "vz_mps", kMilli},
    {"num_frames", W::U32}, {"detection_camera_rot", W::F32, 9}, {"detection_camera_trans", W::F32, 3},
    {"detection_tag_index", W::U32}, {"detection_camera_type", W::U32}, {"drone_camera_rot", W::F32, 9},
    {"drone_camera_trans", W::F32, 3}};
constexpr FieldSpec kTime[] = {{"time", W::U32}};
constexpr FieldSpec kRawMeasures[] = {
    {"raw_accs", W::U16, 3}, {"raw_gyros", W::I16, 3}, {"raw_gyros_110", W::I16, 2},
    {"vbat_raw", W::U32, 1, "vbat_raw_mv", 1.0}, {"us_debut_echo", W::U16}, {"us_fin_echo", W::U16},
    {"us_association_echo", W::U16}, {"us_distance_echo", W::U16}, {"us_courbe_temps", W::U16},
    {"us_courbe_valeur", W::U16}, {"us_courbe_ref", W::U16}, {"flag_echo_ini", W::U16}, {"nb_echo", W::U16},
    {"sum_echo", W::U32}, {"alt_temp_raw", W::I32, 1, "alt_temp_raw_m", kMilli}, {"gradient", W::I16}};
constexpr FieldSpec kPhysMeasures[] = {
    {"accs_temp", W::F32}, {"gyro_temp", W::U16}, {"phys_accs", W::F32, 3, "phys_accs_mps2", 9.80665e-3},
    {"phys_gyros", W::F32, 3, "phys_gyros_radps", 0.017453292519943295}, {"alim3v3", W::U32},
    {"vref_epson", W::U32}, {"vref_idg", W::U32}};
constexpr FieldSpec kGyrosOffsets[] = {{"offset_g", W::F32, 3}};
constexpr FieldSpec kEulerAngles[] = {{"theta_a", W::F32, 1, "theta_a_deg", kMilli},
                                      {"phi_a", W::F32, 1, "phi_a_deg", kMilli}};
constexpr FieldSpec kReferences[] = {
    {"ref_theta", W::I32}, {"ref_phi", W::I32}, {"ref_theta_i", W::I32}, {"ref_phi_i", W::I32},
    {"ref_pitch", W::I32}, {"ref_roll", W::I32}, {"ref_yaw", W::I32}, {"ref_psi", W::I32},
    {"vx_ref", W::F32}, {"vy_ref", W::F32}, {"theta_mod", W::F32}, {"phi_mod", W::F32}, {"k_v_x", W::F32},
    {"k_v_y", W::F32}, {"k_mode", W::U32}, {"ui_time", W::F32}, {"ui_theta", W::F32}, {"ui_phi", W::F32},
    {"ui_psi", W::F32}, {"ui_psi_accuracy", W::F32}, {"ui_seq", W::I32}};
constexpr FieldSpec kTrims[] = {{"angular_rates_trim_r", W::F32}, {"euler_angles_trim_theta", W::F32},
                                {"euler_angles_trim_phi", W::F32}};
constexpr FieldSpec kRcReferences[] = {{"rc_ref_pitch", W::I32}, {"rc_ref_roll", W::I32}, {"rc_ref_yaw", W::I32},
                                       {"rc_ref_gaz", W::I32}, {"rc_ref_ag", W::I32}};
// Drone 2 firmware sends the structure up to altitude_der (76 bytes in real captures).
constexpr FieldSpec kPwm[] = {
    {"motor", W::U8, 4}, {"sat_motor", W::U8, 4}, {"gaz_feed_forward", W::F32}, {"gaz_altitude", W::F32},
    {"altitude_integral", W::F32}, {"vz_ref", W::F32}, {"u_pitch", W::I32}, {"u_roll", W::I32},
    {"u_yaw", W::I32}, {"yaw_u_i", W::F32}, {"u_pitch_planif", W::I32}, {"u_roll_planif", W::I32},
    {"u_yaw_planif", W::I32}, {"u_gaz_planif", W::F32}, {"current_motor", W::U16, 4}, {"altitude_prop", W::F32},
    {"altitude_der", W::F32}};
constexpr FieldSpec kAltitude[] = {
    {"altitude_vision", W::I32, 1, "altitude_vision_m", kMilli}, {"altitude_vz", W::F32, 1, "altitude_vz_mps", kMilli},
    {"altitude_ref", W::I32, 1, "altitude_ref_m", kMilli}, {"altitude_raw", W::I32, 1, "altitude_raw_m", kMilli},
    {"obs_acc_z", W::F32}, {"obs_alt", W::F32}, {"obs_x", W::F32, 3}, {"obs_state", W::U32},
    {"est_vb", W::F32, 2}, {"est_state", W::U32}};
constexpr FieldSpec kVisionRaw[] = {{"vision_tx_raw", W::F32}, {"vision_ty_raw", W::F32}, {"vision_tz_raw", W::F32}};
constexpr FieldSpec kVisionOf[] = {{"of_dx", W::F32, 5}, {"of_dy", W::F32, 5}};
constexpr FieldSpec kVision[] = {
    {"vision_state", W::U32}, {"vision_misc", W::I32}, {"vision_phi_trim", W::F32},
    {"vision_phi_ref_prop", W::F32}, {"vision_theta_trim", W::F32}, {"vision_theta_ref_prop", W::F32},
    {"new_raw_picture", W::I32}, {"theta_capture", W::F32}, {"phi_capture", W::F32}, {"psi_capture", W::F32},
    {"altitude_capture", W::I32}, {"time_capture", W::U32}, {"body_v", W::F32, 3}, {"delta_phi", W::F32},
    {"delta_theta", W::F32}, {"delta_psi", W::F32}, {"gold_defined", W::U32}, {"gold_reset", W::U32},
    {"gold_x", W::F32}, {"gold_y", W::F32}};
constexpr FieldSpec kVisionPerf[] = {{"time_szo", W::F32}, {"time_corners", W::F32}, {"time_compute", W::F32},
                                     {"time_tracking", W::F32}, {"time_trans", W::F32}, {"time_update", W::F32},
                                     {"time_custom", W::F32, 20}};
constexpr FieldSpec kTrackersSend[] = {{"locked", W::I32, 30}, {"point", W::I32, 60}};
constexpr FieldSpec kVisionDetect[] = {
    {"nb_detected", W::U32}, {"type", W::U32, 4}, {"xc", W::U32, 4}, {"yc", W::U32, 4}, {"width", W::U32, 4},
    {"height", W::U32, 4}, {"dist", W::U32, 4}, {"orientation_angle", W::F32, 4}, {"rotation", W::F32, 36},
    {"translation", W::F32, 12}, {"camera_source", W::U32, 4}};
constexpr FieldSpec kWatchdog[] = {{"watchdog", W::I32}};
constexpr FieldSpec kAdcDataFrame[] = {{"version", W::U32}, {"data_frame", W::U8, 32}};
constexpr FieldSpec kVideoStream[] = {
    {"quant", W::U8}, {"frame_size", W::U32}, {"frame_number", W::U32}, {"atcmd_ref_seq", W::U32},
    {"atcmd_mean_ref_gap", W::U32, 1, "atcmd_mean_ref_gap_s", kMilli}, {"atcmd_var_ref_gap", W::F32},
    {"atcmd_ref_quality", W::U32}, {"out_bitrate", W::U32}, {"desired_bitrate", W::U32}, {"data", W::I32, 5},
    {"tcp_queue_level", W::U32}, {"fifo_queue_level", W::U32}};
constexpr FieldSpec kGames[] = {{"double_tap_counter", W::U32}, {"finish_line_counter", W::U32}};
constexpr FieldSpec kPressureRaw[] = {{"up", W::I32}, {"ut", W::I16}, {"temperature_meas", W::I32},
                                      {"pression_meas", W::I32}};
// Drone 2 firmware sends up to error_var (75 bytes in real captures).
constexpr FieldSpec kMagneto[] = {
    {"mx", W::I16}, {"my", W::I16}, {"mz", W::I16}, {"magneto_raw", W::F32, 3}, {"magneto_rectified", W::F32, 3},
    {"magneto_offset", W::F32, 3}, {"heading_unwrapped", W::F32}, {"heading_gyro_unwrapped", W::F32},
    {"heading_fusion_unwrapped", W::F32}, {"magneto_calibration_ok", W::U8}, {"magneto_state", W::U32},
    {"magneto_radius", W::F32}, {"error_mean", W::F32}, {"error_var", W::F32}};
// Drone 2 firmware sends 13 of the 15 floats (56 bytes in real captures).
constexpr FieldSpec kWindSpeed[] = {
    {"wind_speed", W::F32, 1, "wind_speed_mps", 1.0}, {"wind_angle", W::F32, 1, "wind_angle_rad", 1.0},
    {"wind_compensation_theta", W::F32}, {"wind_compensation_phi", W::F32}, {"state_x1", W::F32},
    {"state_x2", W::F32}, {"state_x3", W::F32}, {"state_x4", W::F32}, {"state_x5", W::F32}, {"state_x6", W::F32},
    {"magneto_debug1", W::F32}, {"magneto_debug2", W::F32}, {"magneto_debug3", W::F32}};
constexpr FieldSpec kKalmanPressure[] = {
    {"offset_pressure", W::F32}, {"est_z", W::F32}, {"est_zdot", W::F32}, {"est_bias_pwm", W::F32},
    {"est_biais_pression", W::F32}, {"offset_us", W::F32}, {"prediction_us", W::F32}, {"cov_alt", W::F32},
    {"cov_pwm", W::F32}, {"cov_vitesse", W::F32}, {"bool_effet_sol", W::Bool32}, {"somme_inno", W::F32},
    {"flag_rejet_us", W::Bool32}, {"u_multisinus", W::F32}, {"gaz_altitude", W::F32},
    {"flag_multisinus", W::Bool32}, {"flag_multisinus_debut", W::Bool32}};
constexpr FieldSpec kHdvideoStream[] = {
    {"hdvideo_state", W::U32}, {"storage_fifo_nb_packets", W::U32}, {"storage_fifo_size", W::U32},
    {"usbkey_size", W::U32, 1, "usbkey_size_kb", 1.0}, {"usbkey_freespace", W::U32, 1, "usbkey_freespace_kb", 1.0},
    {"frame_number", W::U32}, {"usbkey_remaining_time", W::U32, 1, "usbkey_remaining_time_s", 1.0}};
constexpr FieldSpec kWifi[] = {{"link_quality", W::U32}};
constexpr FieldSpec kGps[] = {
    {"latitude", W::F64, 1, "latitude_deg", 1.0}, {"longitude", W::F64, 1, "longitude_deg", 1.0},
    {"elevation", W::F64, 1, "elevation_m", 1.0}, {"hdop", W::F64}, {"data_available", W::U32},
    {"zero_validated", W::Bool32}, {"wpt_validated", W::Bool32}, {"lat0", W::F64}, {"long0", W::F64},
    {"lat_fused", W::F64}, {"long_fused", W::F64}, {"gps_state", W::U32}, {"x_traj", W::F32}, {"x_ref", W::F32},
    {"y_traj", W::F32}, {"y_ref", W::F32}, {"theta_p", W::F32}, {"phi_p", W::F32}, {"theta_i", W::F32},
    {"phi_i", W::F32}, {"theta_d", W::F32}, {"phi_d", W::F32}, {"vdop", W::F64}, {"pdop", W::F64},
    {"speed", W::F32, 1, "speed_mps", 1.0}, {"last_frame_timestamp", W::U32}, {"degree", W::F32},
    {"degree_magnetic", W::F32}, {"ehpe", W::F32}, {"ehve", W::F32}, {"c_n0", W::F32}, {"nbsat", W::U32},
    {"channels", W::U8, 24}, {"is_gps_plugged", W::Bool32}, {"ephemeris_status", W::U32}, {"vx_traj", W::F32},
    {"vy_traj", W::F32}, {"firmware_status", W::U32}};

constexpr std::array<NavdataOptionSpec, kKnownOptionCount> kOptions = {{
    {kTagDemo, "demo", 148, kDemo},
    {kTagTime, "time", 8, kTime},
    {kTagRawMeasures, "raw_measures", 52, kRawMeasures},
    {kTagPhysMeasures, "phys_measures", 46, kPhysMeasures},
    {kTagGyrosOffsets, "gyros_offsets", 16, kGyrosOffsets},
    {kTagEulerAngles, "euler_angles", 12, kEulerAngles},
    {kTagReferences, "references", 88, kReferences},
    {kTagTrims, "trims", 16, kTrims},
    {kTagRcReferences, "rc_references", 24, kRcReferences},
    {kTagPwm, "pwm", 76, kPwm},
    {kTagAltitude, "altitude", 56, kAltitude},
    {kTagVisionRaw, "vision_raw", 16, kVisionRaw},
    {kTagVisionOf, "vision_of", 44, kVisionOf},
    {kTagVision, "vision", 92, kVision},
    {kTagVisionPerf, "vision_perf", 108, kVisionPerf},
    {kTagTrackersSend, "trackers_send", 364, kTrackersSend},
    {kTagVisionDetect, "vision_detect", 328, kVisionDetect},
    {kTagWatchdog, "watchdog", 8, kWatchdog},
    {kTagAdcDataFrame, "adc_data_frame", 40, kAdcDataFrame},
    {kTagVideoStream, "video_stream", 65, kVideoStream},
    {kTagGames, "games", 12, kGames},
    {kTagPressureRaw, "pressure_raw", 18, kPressureRaw},
    {kTagMagneto, "magneto", 75, kMagneto},
    {kTagWindSpeed, "wind_speed", 56, kWindSpeed},
    {kTagKalmanPressure, "kalman_pressure", 72, kKalmanPressure},
    {kTagHdvideoStream, "hdvideo_stream", 32, kHdvideoStream},
    {kTagWifi, "wifi", 8, kWifi},
    {kTagGps, "gps", 216, kGps},
}};

constexpr std::array<std::string_view, 32> kStateBitNames = {
    "flying", "video_enabled", "vision_enabled", "control_algorithm", "altitude_control", "start_button",
    "command_ack", "camera_ready", "travelling", "usb", "navdata_demo", "navdata_bootstrap", "motors_problem",
    "com_lost", "software_fault", "battery_low", "user_emergency", "timer_elapsed", "magneto_needs_calibration",
    "angles_out_of_range", "too_much_wind", "ultrasound_deaf", "cutout", "pic_version_ok", "atcodec_thread_on",
    "navdata_thread_on", "video_thread_on", "acquisition_thread_on", "control_watchdog", "adc_watchdog",
    "com_watchdog", "emergency"};

constexpr std::array<std::string_view, 10> kControlStates = {
    "default", "init", "landed", "flying", "hovering", "test", "takeoff", "gotofix", "landing", "looping"};

}  // namespace

std::size_t wire_size(WireType type) {
  switch (type) {
    case W::U8: return 1;
    case W::I16:
    case W::U16: return 2;
    case W::I32:
    case W::U32:
    case W::F32:
    case W::Bool32: return 4;
    case W::F64: return 8;
  }
  return 0;
}

std::size_t NavdataOptionSpec::value_count() const {
  std::size_t n = 0;
  for (const auto& f : fields) n += f.count;
  return n;
}

std::span<const NavdataOptionSpec> navdata_option_specs() { return kOptions; }

const NavdataOptionSpec* find_option_spec(std::uint16_t tag) {
  return tag < kOptions.size() ? &kOptions[tag] : nullptr;
}

std::optional<std::size_t> field_value_index(const NavdataOptionSpec& spec, std::string_view field_name) {
  std::size_t index = 0;
  for (const auto& f : spec.fields) {
    if (f.name == field_name) return index;
    index += f.count;
  }
  return std::nullopt;
}

std::string_view state_bit_name(int bit) {
  return bit >= 0 && bit < 32 ? kStateBitNames[static_cast<std::size_t>(bit)] : std::string_view("?");
}

std::string_view control_state_name(int major) {
  return major >= 0 && major < static_cast<int>(kControlStates.size()) ? kControlStates[static_cast<std::size_t>(major)]
                                                                        : std::string_view("unknown");
}

}  // namespace labo::ardrone2
