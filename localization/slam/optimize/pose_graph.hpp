#pragma once
// Pose-graph optimisation over Sim(3), for loop closure. Nodes are keyframe similarities S_k (map ->
// camera k); an edge (i, j) holds a measured relative similarity S_i * S_j^-1 and pulls the nodes
// towards it. Edges measured from the current keyframe poses (neighbours in time, covisible pairs)
// hold the map's local shape; a loop edge, measured by matching the current keyframe against an old
// one, disagrees with them by the drift accumulated around the loop, and the optimisation spreads that
// error over the graph. Residual per edge: E = measured^-1 * S_i * S_j^-1 written as
// (angle-axis of R_E, t_E, log s_E), each divided by its sigma. Solved with Ceres (Levenberg-Marquardt,
// sparse Cholesky), one thread.
#include <map>
#include <set>
#include <vector>

#include "localization/slam/optimize/sim3.hpp"

namespace labo::slam {

struct PoseGraphEdge {
  int i = -1, j = -1;
  Similarity3 measured_ij;   // S_i * S_j^-1
  double weight = 1.0;       // multiplies the inverse sigmas
};

struct PoseGraph {
  std::map<int, Similarity3> nodes;  // keyframe id -> S_k (map -> camera)
  std::set<int> fixed;               // gauge: at least one node
  std::vector<PoseGraphEdge> edges;
};

struct PoseGraphSettings {
  int max_iterations = 100;
  double rotation_sigma_rad = 0.01;
  double translation_sigma = 0.01;  // map units (the initial median depth is 1)
  double log_scale_sigma = 0.01;
};

struct PoseGraphReport {
  bool solved = false;
  int iterations = 0;
  double initial_cost = 0, final_cost = 0;
};

// Optimises graph.nodes in place (fixed nodes stay). Edges naming unknown nodes are ignored.
PoseGraphReport optimize_pose_graph(PoseGraph& graph, const PoseGraphSettings& settings = {});

}  // namespace labo::slam
