#include "drone/ardrone2/config_handshake.hpp"

namespace labo::ardrone2 {

ConfigTick ConfigHandshake::tick(Seconds t, bool ack, bool alive, AtCommandEncoder& encoder, std::string& out) {
  ConfigTick result;
  switch (phase_) {
    case Phase::Idle:
      if (!alive || queue_.empty()) return result;
      if (ack) {  // a stale acknowledgement: clear it first
        encoder.ctrl(out, kCtrlAckConfig);
        return result;
      }
      // The SDK always sends CONFIG_IDS right before a CONFIG; default IDs are "00000000".
      encoder.config_ids(out, "00000000", "00000000", "00000000");
      encoder.config(out, queue_.front().key, queue_.front().value);
      result.sent = true;
      sent_t_ = t;
      phase_ = Phase::AwaitAck;
      return result;
    case Phase::AwaitAck:
      if (ack) {
        result.acked = std::move(queue_.front());
        queue_.pop_front();
        encoder.ctrl(out, kCtrlAckConfig);
        phase_ = Phase::AwaitAckClear;
      } else if (t - sent_t_ > ack_timeout_s_) {
        result.timed_out = queue_.front().key;
        phase_ = Phase::Idle;
      }
      return result;
    case Phase::AwaitAckClear:
      if (ack) {
        encoder.ctrl(out, kCtrlAckConfig);
      } else {
        phase_ = Phase::Idle;
      }
      return result;
  }
  return result;
}

}  // namespace labo::ardrone2
