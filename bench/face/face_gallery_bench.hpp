#pragma once
// Table 1 over many people (`labodrone-bench bench faces`): the face benchmark (face_bench.hpp) run
// once per face, each face registered from its own frontal frames and tracked through its own rendered
// sequences, with per-face and pooled LM-tracking figures. The faces are scikit-image's astronaut and
// every face the detector finds in the 1927 Solvay conference photograph (group_photo.hpp); a face that
// cannot serve as a portrait is listed with its reason.
#include <filesystem>
#include <functional>
#include <string>
#include <vector>

#include "bench/face/face_bench.hpp"

namespace labo::bench {

struct FaceErrors {
  int frames = 0;
  double tx_mm = 0, ty_mm = 0, tz_mm = 0, roll_deg = 0, yaw_deg = 0, pitch_deg = 0;
};

struct PersonFigures {
  std::string name;
  bool held_out = false;    // never used to tune anything (docs/face.md)
  std::string refused;      // why the face cannot serve ("" when it was measured)
  double portrait_interocular_px = 0;  // the face's resolution in its photograph
  FaceBenchReport report;   // empty when refused
  FaceErrors mean, median;  // LM tracking over the face's posed frames
  double detection_rate = 0;
  std::string main_lost_reason;  // the most frequent, "" when never lost
};

struct FaceGalleryReport {
  std::vector<PersonFigures> people;
  FaceErrors pooled_mean, pooled_median;  // over every posed frame of every measured face
  double frame_ms_median = 0;             // whole pipeline, every frame of every face
  int faces_measured = 0;
};

struct FaceGalleryOptions {
  FaceBenchOptions bench;                    // sequences, frames, seed, video, cameras, lab
  std::filesystem::path astronaut;           // assets/astronaut.png ("" to leave it out)
  std::filesystem::path group_photo;         // assets/solvay_1927.png
  int max_faces = 100;                       // at most this many faces measured, in gallery order
  bool tuning_faces_only = false;            // leave the held-out faces out (for tuning runs)
  std::string only_face;                     // when set, that face alone
  std::filesystem::path crops_dir;           // when set, each face's photograph is written there
};

// Every third face of the gallery (03, 06, ...) is held out of tuning.
bool held_out_of_tuning(int gallery_rank);

FaceGalleryReport run_face_gallery_bench(const face::FaceConfig& config, const PinholeCamera& camera,
                                         const FaceGalleryOptions& options,
                                         const std::function<void(const std::string&)>& progress = {});

}  // namespace labo::bench
