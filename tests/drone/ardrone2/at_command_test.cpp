#include <catch2/catch.hpp>
#include <string>
#include <vector>

#include "drone/ardrone2/at_command.hpp"

using namespace labo::ardrone2;

TEST_CASE("link: AT floats travel as their IEEE-754 bits", "[link]") {
  CHECK(float_to_at_int(-0.8f) == -1085485875);
  CHECK(float_to_at_int(0.5f) == 1056964608);
  CHECK(float_to_at_int(1.0f) == 1065353216);
  CHECK(at_int_to_float(-1085485875) == -0.8f);
}

TEST_CASE("link: golden AT command strings", "[link]") {
  AtCommandEncoder enc;
  std::string out;
  enc.ref(out, true, false);
  CHECK(out == "AT*REF=1,290718208\r");
  out.clear();
  enc.ref(out, false, false);
  CHECK(out == "AT*REF=2,290717696\r");
  out.clear();
  enc.ref(out, false, true);
  CHECK(out == "AT*REF=3,290717952\r");
  out.clear();
  enc.pcmd(out, WirePcmd{false, -0.8f, 0.5f, 1.0f, 0.0f});
  CHECK(out == "AT*PCMD=4,1,-1085485875,1056964608,1065353216,0\r");
  out.clear();
  enc.pcmd(out, WirePcmd{true, 0.3f, 0.3f, 0.3f, 0.3f});
  CHECK(out == "AT*PCMD=5,0,0,0,0,0\r");
  out.clear();
  enc.pcmd(out, WirePcmd{false, 2.0f, -3.0f, 0.0f, 0.0f});  // clipped to [-1, 1]
  CHECK(out == "AT*PCMD=6,1,1065353216,-1082130432,0,0\r");
  out.clear();
  enc.pcmd_mag(out, WirePcmd{false, 0, 0, 0, 0.5f}, 0.0f, 1.0f);
  CHECK(out == "AT*PCMD_MAG=7,1,0,0,0,1056964608,0,1065353216\r");
  out.clear();
  enc.ftrim(out);
  enc.config_ids(out, "00000000", "00000000", "00000000");
  enc.config(out, "general:navdata_demo", "TRUE");
  enc.ctrl(out, kCtrlAckConfig);
  enc.comwdg(out);
  enc.calib(out, 0);
  CHECK(out == "AT*FTRIM=8\rAT*CONFIG_IDS=9,\"00000000\",\"00000000\",\"00000000\"\r"
               "AT*CONFIG=10,\"general:navdata_demo\",\"TRUE\"\rAT*CTRL=11,5,0\rAT*COMWDG=12\rAT*CALIB=13,0\r");
  enc.reset_sequence();
  CHECK(enc.next_sequence() == 1);
}

TEST_CASE("link: AT parser reads what the encoder writes, CR or LF", "[link]") {
  AtCommandEncoder enc;
  std::string out;
  enc.ref(out, true, false);
  enc.pcmd(out, WirePcmd{false, -0.8f, 0.0f, 0.25f, 0.0f});
  enc.config(out, "video:video_channel", "1");
  AtCommandParser parser;
  std::vector<AtCommand> cmds;
  auto report = parser.parse(out, cmds);
  REQUIRE(report.commands == 3);
  CHECK(report.malformed == 0);
  CHECK(cmds[0].name == "REF");
  CHECK(static_cast<std::uint32_t>(cmds[0].args[0].integer) == 290718208u);
  CHECK(cmds[1].name == "PCMD");
  CHECK(cmds[1].sequence == 2);
  CHECK(cmds[1].float_arg(1) == -0.8f);
  CHECK(cmds[1].float_arg(3) == 0.25f);
  CHECK(cmds[2].args[0].is_string);
  CHECK(cmds[2].args[1].text == "1");

  report = parser.parse("AT*FTRIM=5\nAT*COMWDG=6\r\n", cmds);
  CHECK(report.commands == 2);
  CHECK(cmds[1].name == "COMWDG");
}

TEST_CASE("link: AT parser refuses bad datagrams with a reason", "[link]") {
  AtCommandParser parser;
  std::vector<AtCommand> cmds;
  std::string big(1025, 'A');
  auto r = parser.parse(big, cmds);
  CHECK(r.datagram_too_long);
  CHECK(cmds.empty());
  r = parser.parse("AT*REF=1,290718208", cmds);  // no terminator
  CHECK(r.commands == 0);
  CHECK(r.malformed == 1);
  CHECK(r.first_error.find("terminator") != std::string::npos);
  r = parser.parse("AT*REF=x,1\rAT*PCMD=2,1,0,0,0\rAT*CONFIG=3,\"a\r", cmds);
  CHECK(r.commands == 0);
  CHECK(r.malformed == 3);
  r = parser.parse("garbage\rAT*FTRIM=9\r", cmds);
  CHECK(r.commands == 1);
  CHECK(r.malformed == 1);
  r = parser.parse("AT*REF=0,1\r", cmds);  // seq must be positive
  CHECK(r.malformed == 1);
  r = parser.parse("AT*REF=1,99999999999\r", cmds);  // beyond 32 bits
  CHECK(r.malformed == 1);
}

TEST_CASE("link: AT sequence rule drops old commands, seq 1 resets", "[link]") {
  AtSequenceFilter f;
  CHECK(f.accept(1));
  CHECK(f.accept(5));
  CHECK_FALSE(f.accept(5));
  CHECK_FALSE(f.accept(3));
  CHECK(f.accept(6));
  CHECK(f.accept(1));
  CHECK(f.accept(2));
}
