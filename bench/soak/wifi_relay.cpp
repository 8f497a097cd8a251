#include "bench/soak/wifi_relay.hpp"

#include <array>
#include <boost/asio/steady_timer.hpp>
#include <boost/asio/write.hpp>
#include <vector>

namespace labo::bench {

namespace asio = boost::asio;
using asio::ip::tcp;
using asio::ip::udp;

namespace {
const asio::ip::address kLoopback = asio::ip::make_address("127.0.0.1");
constexpr auto kCutPoll = std::chrono::milliseconds(20);
}  // namespace

// One UDP channel: the driver's datagrams go to the emulator from a socket of the relay's own, and
// the emulator's answers (navdata) to that socket go back to the driver's last address.
class WifiRelay::Datagrams {
 public:
  Datagrams(WifiRelay& relay, int emulator_port)
      : relay_(relay), driver_side_(relay.io_, udp::endpoint(kLoopback, 0)), drone_side_(relay.io_, udp::endpoint(kLoopback, 0)),
        emulator_(kLoopback, static_cast<unsigned short>(emulator_port)) {
    receive_from_driver();
    receive_from_drone();
  }
  int port() const { return driver_side_.local_endpoint().port(); }

 private:
  void receive_from_driver() {
    driver_side_.async_receive_from(asio::buffer(up_), driver_, [this](boost::system::error_code ec, std::size_t n) {
      if (ec == asio::error::operation_aborted) return;
      have_driver_ = true;
      if (!ec) forward(drone_side_, up_, n, emulator_);
      receive_from_driver();
    });
  }
  void receive_from_drone() {
    // Errors here are ICMP "port unreachable" while the emulator restarts: keep listening.
    drone_side_.async_receive_from(asio::buffer(down_), from_drone_, [this](boost::system::error_code ec, std::size_t n) {
      if (ec == asio::error::operation_aborted) return;
      if (!ec && have_driver_) forward(driver_side_, down_, n, driver_);
      receive_from_drone();
    });
  }
  // Synchronous send on the io thread: a loopback datagram does not block.
  void forward(udp::socket& via, const std::array<char, 65536>& bytes, std::size_t n, const udp::endpoint& to) {
    if (relay_.cut()) {
      ++relay_.datagrams_lost_;
      return;
    }
    boost::system::error_code ignored;
    via.send_to(asio::buffer(bytes.data(), n), to, 0, ignored);
  }

  WifiRelay& relay_;
  udp::socket driver_side_, drone_side_;
  udp::endpoint emulator_, driver_, from_drone_;
  bool have_driver_ = false;
  std::array<char, 65536> up_{}, down_{};
};

// The video's TCP stream: one pair of connections at a time, each direction pumped by one read and
// one write in flight; during a cut the data read waits, and no more is read.
class WifiRelay::VideoStream {
 public:
  VideoStream(WifiRelay& relay, int emulator_port)
      : relay_(relay), acceptor_(relay.io_, tcp::endpoint(kLoopback, 0)),
        emulator_(kLoopback, static_cast<unsigned short>(emulator_port)) {
    accept();
  }
  int port() const { return acceptor_.local_endpoint().port(); }

 private:
  struct Pair : std::enable_shared_from_this<Pair> {
    Pair(WifiRelay& r, tcp::socket driver_socket)
        : relay(r), driver(std::move(driver_socket)), drone(r.io_) {}
    void close() {
      boost::system::error_code ignored;
      driver.close(ignored);
      drone.close(ignored);
    }
    // Moves bytes from `from` to `to` with `buffer`, forever, until either side fails.
    void pump(tcp::socket& from, tcp::socket& to, std::vector<char>& buffer) {
      from.async_read_some(asio::buffer(buffer), [self = shared_from_this(), &from, &to, &buffer](boost::system::error_code ec,
                                                                                                  std::size_t n) {
        if (ec) return self->close();
        self->deliver(from, to, buffer, n);
      });
    }
    void deliver(tcp::socket& from, tcp::socket& to, std::vector<char>& buffer, std::size_t n) {
      if (relay.cut()) {
        // The stream stalls: the bytes read wait for the end of the cut, and nothing more is read.
        auto waiter = std::make_shared<asio::steady_timer>(relay.io_, kCutPoll);
        waiter->async_wait([self = shared_from_this(), waiter, &from, &to, &buffer, n](boost::system::error_code) {
          self->deliver(from, to, buffer, n);
        });
        return;
      }
      asio::async_write(to, asio::buffer(buffer.data(), n),
                        [self = shared_from_this(), &from, &to, &buffer](boost::system::error_code ec, std::size_t) {
                          if (ec) return self->close();
                          self->pump(from, to, buffer);
                        });
    }

    WifiRelay& relay;
    tcp::socket driver, drone;
    std::vector<char> to_drone = std::vector<char>(4096), to_driver = std::vector<char>(65536);
  };

  void accept() {
    acceptor_.async_accept([this](boost::system::error_code ec, tcp::socket socket) {
      if (ec == asio::error::operation_aborted) return;
      if (!ec) connect(std::move(socket));
      accept();
    });
  }
  void connect(tcp::socket driver_socket) {
    ++relay_.video_connections_;
    if (auto old = current_.lock()) old->close();
    auto pair = std::make_shared<Pair>(relay_, std::move(driver_socket));
    current_ = pair;
    pair->drone.async_connect(emulator_, [pair](boost::system::error_code ec) {
      if (ec) return pair->close();  // the emulator is down: the driver reconnects later
      pair->pump(pair->driver, pair->drone, pair->to_drone);
      pair->pump(pair->drone, pair->driver, pair->to_driver);
    });
  }

  WifiRelay& relay_;
  tcp::acceptor acceptor_;
  tcp::endpoint emulator_;
  std::weak_ptr<Pair> current_;
};

WifiRelay::WifiRelay(int emulator_at_port, int emulator_navdata_port, int emulator_video_port)
    : at_(std::make_unique<Datagrams>(*this, emulator_at_port)),
      navdata_(std::make_unique<Datagrams>(*this, emulator_navdata_port)),
      video_(std::make_unique<VideoStream>(*this, emulator_video_port)),
      thread_([this] { io_.run(); }) {}

WifiRelay::~WifiRelay() {
  io_.stop();
  if (thread_.joinable()) thread_.join();
}

int WifiRelay::at_port() const { return at_->port(); }
int WifiRelay::navdata_port() const { return navdata_->port(); }
int WifiRelay::video_port() const { return video_->port(); }

void WifiRelay::cut_for(double seconds) {
  const auto until = Clock::now() + std::chrono::duration_cast<Clock::duration>(std::chrono::duration<double>(seconds));
  cut_until_ = until.time_since_epoch().count();
}

bool WifiRelay::cut() const { return Clock::now().time_since_epoch().count() < cut_until_.load(); }

}  // namespace labo::bench
