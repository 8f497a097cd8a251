#pragma once
// Buffers for wire messages that every client shares: a message is built once into a pooled string
// and handed out as a shared pointer; the buffer is reused once every client has let go of it, so
// steady-state publishing does not allocate. A buffer still held by a slow client is skipped; the
// pool grows only while more messages are in flight than it holds, which the clients' bounded
// queues bound.
#include <memory>
#include <string>
#include <vector>

namespace labo::server {

class WireBufferPool {
 public:
  explicit WireBufferPool(std::size_t size = 8, std::size_t reserve_bytes = 0);
  // A buffer nobody else holds (its old content is still there: resize or clear it).
  std::shared_ptr<std::string> acquire();
  std::size_t size() const { return pool_.size(); }

 private:
  std::vector<std::shared_ptr<std::string>> pool_;
  std::size_t reserve_bytes_;
};

}  // namespace labo::server
