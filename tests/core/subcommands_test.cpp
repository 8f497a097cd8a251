#include "core/subcommands.hpp"

#include <catch2/catch.hpp>
#include <iostream>
#include <sstream>

#include "tests/support/cout_capture.hpp"

using namespace labo;

namespace {

// Redirects std::cerr for as long as it lives.
class CerrCapture {
 public:
  CerrCapture() : old_(std::cerr.rdbuf(out_.rdbuf())) {}
  ~CerrCapture() { std::cerr.rdbuf(old_); }
  CerrCapture(const CerrCapture&) = delete;
  CerrCapture& operator=(const CerrCapture&) = delete;
  std::string text() const { return out_.str(); }

 private:
  std::ostringstream out_;
  std::streambuf* old_;
};

const CommandSpec& greet_spec() {
  static const CommandSpec spec{"say hello", "NAME", "Greets.", {{"--loud", "", "shout"}}, 1, 1};
  return spec;
}

Program test_program(std::string* greeted) {
  return {.name = "prog",
          .about = "A test program.",
          .commands = {{greet_spec(),
                        [greeted](const ParsedArgs& a) {
                          *greeted = a.positionals.at(0) + (a.flag("--loud") ? "!" : "");
                          return 0;
                        }}},
          .moved = {{"bench", "prog-bench"}}};
}

}  // namespace

TEST_CASE("subcommands: a command of several words runs with its options") {
  std::string greeted;
  CHECK(run_program(test_program(&greeted), {"say", "hello", "ada", "--loud"}) == 0);
  CHECK(greeted == "ada!");
}

TEST_CASE("subcommands: bad arguments, unknown and moved commands exit 2 with the reason") {
  std::string greeted;
  const Program p = test_program(&greeted);
  {
    CerrCapture err;
    CHECK(run_program(p, {"say", "hello"}) == 2);
    CHECK_THAT(err.text(), Catch::StartsWith("prog say hello: "));
  }
  {
    CerrCapture err;
    CHECK(run_program(p, {"say", "hello", "ada", "--quiet"}) == 2);
    CHECK_THAT(err.text(), Catch::Contains("--quiet"));
  }
  {
    CerrCapture err;
    CHECK(run_program(p, {"fly"}) == 2);
    CHECK(err.text() == "prog: unknown command 'fly' (see prog --help)\n");
  }
  {
    CerrCapture err;
    CHECK(run_program(p, {"bench", "planar", "--json"}) == 2);
    CHECK(err.text() == "prog: 'bench' commands are in prog-bench: run 'prog-bench bench planar --json'\n");
  }
  CHECK(greeted.empty());
}

TEST_CASE("subcommands: --help lists the commands, no arguments prints it and exits 2") {
  std::string greeted;
  const Program p = test_program(&greeted);
  {
    test::CoutCapture out;
    CHECK(run_program(p, {"--help"}) == 0);
    CHECK_THAT(out.text(), Catch::Contains("say hello NAME") && Catch::Contains("Greets."));
  }
  {
    test::CoutCapture out;
    CHECK(run_program(p, {}) == 2);
    CHECK_THAT(out.text(), Catch::StartsWith("usage: prog <command>"));
  }
  {
    test::CoutCapture out;
    CHECK(run_program(p, {"say", "hello", "--help"}) == 0);
    CHECK_THAT(out.text(), Catch::Contains("--loud"));
    CHECK_THAT(out.text(), Catch::StartsWith("usage: prog say hello"));  // the binary that has the command
  }
}

TEST_CASE("subcommands: a command that throws exits 1 with its message") {
  static const CommandSpec spec{"boom", "", "Fails.", {}, 0, 0};
  const Program p{.name = "prog", .about = "", .commands = {{spec, [](const ParsedArgs&) -> int { throw std::runtime_error("disk full"); }}}, .moved = {}};
  CerrCapture err;
  CHECK(run_program(p, {"boom"}) == 1);
  CHECK(err.text() == "prog boom: disk full\n");
}
