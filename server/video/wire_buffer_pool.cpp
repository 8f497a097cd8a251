#include "server/video/wire_buffer_pool.hpp"

namespace labo::server {

WireBufferPool::WireBufferPool(std::size_t size, std::size_t reserve_bytes) : pool_(size), reserve_bytes_(reserve_bytes) {
  for (auto& b : pool_) {
    b = std::make_shared<std::string>();
    b->reserve(reserve_bytes_);
  }
}

std::shared_ptr<std::string> WireBufferPool::acquire() {
  for (auto& b : pool_)
    if (b.use_count() == 1) return b;
  pool_.push_back(std::make_shared<std::string>());
  pool_.back()->reserve(reserve_bytes_);
  return pool_.back();
}

}  // namespace labo::server
