#pragma once
// The soak's watchers, on their own thread: spectators who join (half of them on the H.264 path,
// half on JPEG), watch for a while and leave, never more than a few at once; and one slow reader who
// reads for a few seconds, then nothing for a long time, with a 4 KiB receive buffer so its backlog
// lands on the server at once. The server must cut it off or drop it to the next frame; when it
// finds itself cut off it comes back.
#include <atomic>
#include <boost/asio/io_context.hpp>
#include <cstdint>
#include <memory>
#include <random>
#include <string>
#include <thread>
#include <vector>

#include "bench/soak/soak_client.hpp"

namespace labo::bench {

struct AudienceOptions {
  int max_spectators = 4;
  double join_every_s = 15;
  double stay_min_s = 30, stay_max_s = 120;
  double slow_read_s = 5;    // the slow reader reads this long,
  double slow_stall_s = 60;  // then nothing for this long
  unsigned seed = 1;
};

struct AudienceCounts {
  std::uint64_t spectators_joined = 0, slow_reader_stalls = 0, slow_reader_cut_off = 0, connect_failures = 0;
  std::uint64_t frames_received = 0;  // by spectators (the slow reader's not counted)
};

class SoakAudience {
 public:
  // `cookies`: logged-in sessions the watchers use, in turn.
  SoakAudience(boost::asio::io_context& io, unsigned short port, std::vector<std::string> cookies, AudienceOptions options);
  ~SoakAudience();
  void stop();  // everyone leaves
  AudienceCounts counts() const;

 private:
  struct Spectator {
    std::shared_ptr<SoakClient> client;
    double leave_at_s = 0;
  };
  void run();
  void join(double now_s);
  void leave_due(double now_s, bool everyone);
  void drive_slow_reader(double now_s);
  std::shared_ptr<SoakClient> connect(bool small_buffer);

  boost::asio::io_context& io_;
  unsigned short port_;
  std::vector<std::string> cookies_;
  AudienceOptions options_;
  std::mt19937 random_;
  std::atomic<bool> running_{true};
  std::vector<Spectator> spectators_;  // audience thread only
  std::shared_ptr<SoakClient> slow_;
  bool slow_stalled_ = false;
  double slow_switch_at_s_ = 0;
  std::size_t next_cookie_ = 0;
  std::atomic<std::uint64_t> joined_{0}, stalls_{0}, cut_off_{0}, failures_{0}, left_frames_{0};
  std::thread thread_;
};

}  // namespace labo::bench
