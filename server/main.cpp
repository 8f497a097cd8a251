// labodrone: the product's binary, one subcommand per job. `labodrone --help` lists them; each has
// --help. The lab bench (benchmarks and experiments) is `labodrone-bench` (bench/main.cpp).
#include <string>
#include <vector>

#include "core/subcommands.hpp"
#include "drone/ardrone2/inspect_commands.hpp"
#include "drone/lab/lab_commands.hpp"
#include "drone/sim/emulate_command.hpp"
#include "drone/sim/render_commands.hpp"
#include "drone/tello/tello_state_command.hpp"
#include "localization/face/face_commands.hpp"
#include "localization/face/teacher_head.hpp"
#include "localization/planar/planar_commands.hpp"
#include "server/hash_password_command.hpp"
#include "server/serve_command.hpp"

namespace {

// The simulated teacher's face for the commands that run the simulated lab (drone/ cannot call
// localization/).
labo::sim::TexturedHeadModel teacher_head(const labo::lab::LabDescription& lab) { return labo::face::load_lab_teacher_head(lab); }

labo::Program program() {
  using namespace labo;
  using namespace labo::server;
  using namespace labo::sim;
  using namespace labo::lab;
  using namespace labo::ardrone2;
  using namespace labo::tello;
  return {
      .name = "labodrone",
      .about = "LaboDrone flies an AR.Drone 2.0 or a Tello (or the simulated lab) through a remote electronics lab.\n"
               "Benchmarks and experiments are in labodrone-bench.",
      .commands =
          {
              {serve_command_spec(), run_serve_command},
              {emulate_command_spec(), [](const ParsedArgs& a) { return run_emulate_command(a, teacher_head); }},
              {navdata_command_spec(), run_navdata_command},
              {video_command_spec(), run_video_command},
              {tello_state_command_spec(), run_tello_state_command},
              {planar::homography_command_spec(), planar::run_homography_command},
              {face_register_command_spec(), run_face_register_command},
              {hash_password_command_spec(), run_hash_password_command},
              {sim_lab_command_spec(), run_sim_lab_command},
              {sim_render_command_spec(), [](const ParsedArgs& a) { return run_sim_render_command(a, teacher_head); }},
              {sim_textures_command_spec(), run_sim_textures_command},
          },
      .moved = {{"bench", "labodrone-bench"},
                {"sim inspect", "labodrone-bench"},
                {"sim perturb", "labodrone-bench"},
                {"sim face-follow", "labodrone-bench"},
                {"sim compare-slam", "labodrone-bench"},
                {"sim estimate", "labodrone-bench"},
                {"sim realtime", "labodrone-bench"}},
  };
}

}  // namespace

int main(int argc, char** argv) { return labo::run_program(program(), std::vector<std::string>(argv + 1, argv + argc)); }
