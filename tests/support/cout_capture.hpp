#pragma once
// Redirects std::cout into a string for as long as it lives, for tests of commands that print their
// answer (JSON, a summary). Tests only.
#include <iostream>
#include <sstream>
#include <string>

namespace labo::test {

class CoutCapture {
 public:
  CoutCapture() : old_(std::cout.rdbuf(out_.rdbuf())) {}
  ~CoutCapture() { std::cout.rdbuf(old_); }
  CoutCapture(const CoutCapture&) = delete;
  CoutCapture& operator=(const CoutCapture&) = delete;
  std::string text() const { return out_.str(); }

 private:
  std::ostringstream out_;
  std::streambuf* old_;
};

}  // namespace labo::test
