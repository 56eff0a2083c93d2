// landmark_info: quick look at a blind_navigation landmark file, read with
// yaml-cpp the way the paper's C++ action client read it (YAML::LoadFile and
// YAML::const_iterator, section 3.3.7). Proves C++ nodes of an RTAB-Map
// workspace can read the store.
//
//   landmark_info FILE          count, total distance, total duration, bytes per metre
//   landmark_info --list FILE   the same, then every landmark [v, w, d, T, psi]
//
// Output is YAML (key: value). Exit status: 0 ok, 1 bad file (message on
// stderr naming the file and the entry), 2 usage.
#include <yaml-cpp/yaml.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <stdexcept>
#include <string>
#include <vector>

namespace {

const std::string kPrefix = "landmark_";
const char* const kFields[] = {"v", "w", "d", "T", "psi"};
const std::size_t kFieldCount = 5;

struct Landmark {
  std::string label;
  double values[kFieldCount];  // v, w, d, T, psi
};

struct BadFile : std::runtime_error {
  explicit BadFile(const std::string& what) : std::runtime_error(what) {}
};

bool IsLandmarkLabel(const std::string& key, long* index) {
  if (key.compare(0, kPrefix.size(), kPrefix) != 0) return false;
  const std::string digits = key.substr(kPrefix.size());
  if (digits.empty() || digits.find_first_not_of("0123456789") != std::string::npos) {
    throw BadFile(key + ": label must be landmark_<number>");
  }
  *index = std::strtol(digits.c_str(), nullptr, 10);
  return true;
}

Landmark ReadLandmark(const std::string& label, const YAML::Node& entry) {
  if (!entry.IsMap() || !entry["data"] || !entry["data"].IsSequence() ||
      entry["data"].size() != kFieldCount) {
    throw BadFile(label + ": entry must be {data: [v, w, d, T, psi]}");
  }
  Landmark landmark;
  landmark.label = label;
  std::size_t i = 0;
  for (YAML::const_iterator it = entry["data"].begin(); it != entry["data"].end(); ++it, ++i) {
    try {
      landmark.values[i] = it->as<double>();
    } catch (const YAML::Exception&) {
      throw BadFile(label + ": " + kFields[i] + " is not a number");
    }
    if (!std::isfinite(landmark.values[i])) {
      throw BadFile(label + ": " + kFields[i] + " is not finite");
    }
  }
  if (landmark.values[2] < 0.0) throw BadFile(label + ": d is negative");
  if (landmark.values[3] <= 0.0) throw BadFile(label + ": T must be positive");
  return landmark;
}

std::vector<Landmark> LoadLandmarks(const std::string& path) {
  YAML::Node root;
  try {
    root = YAML::LoadFile(path);
  } catch (const YAML::BadFile&) {
    throw BadFile("cannot read the file");
  } catch (const YAML::Exception& error) {
    throw BadFile(std::string("not valid YAML: ") + error.what());
  }
  if (!root.IsMap()) throw BadFile("top level must be a map of landmark entries");
  std::vector<Landmark> landmarks;
  long previous = 0;
  for (YAML::const_iterator it = root.begin(); it != root.end(); ++it) {
    const std::string key = it->first.as<std::string>();
    long index = 0;
    if (!IsLandmarkLabel(key, &index)) continue;  // metadata
    if (index <= previous) throw BadFile(key + ": labels out of recording order");
    previous = index;
    landmarks.push_back(ReadLandmark(key, it->second));
  }
  if (landmarks.empty()) throw BadFile("no landmarks in the file (empty path)");
  return landmarks;
}

long FileBytes(const std::string& path) {
  std::ifstream stream(path, std::ios::binary | std::ios::ate);
  return stream ? static_cast<long>(stream.tellg()) : -1;
}

}  // namespace

int main(int argc, char** argv) {
  bool list = false;
  std::string path;
  for (int i = 1; i < argc; ++i) {
    const std::string arg = argv[i];
    if (arg == "--list") {
      list = true;
    } else if (path.empty() && !arg.empty() && arg[0] != '-') {
      path = arg;
    } else {
      path.clear();
      break;
    }
  }
  if (path.empty()) {
    std::fprintf(stderr, "usage: landmark_info [--list] LANDMARK_FILE.yaml\n");
    return 2;
  }
  std::vector<Landmark> landmarks;
  try {
    landmarks = LoadLandmarks(path);
  } catch (const BadFile& error) {
    std::fprintf(stderr, "landmark_info: %s: %s\n", path.c_str(), error.what());
    return 1;
  }
  double distance = 0.0, duration = 0.0;
  for (const Landmark& landmark : landmarks) {
    distance += landmark.values[2];
    duration += landmark.values[3];
  }
  const long bytes = FileBytes(path);
  std::printf("file: '%s'\n", path.c_str());
  std::printf("landmarks: %zu\n", landmarks.size());
  std::printf("distance_m: %.17g\n", distance);
  std::printf("duration_s: %.17g\n", duration);
  std::printf("bytes: %ld\n", bytes);
  std::printf("bytes_per_m: %.6g\n", distance > 0.0 ? bytes / distance : 0.0);
  if (list) {
    std::printf("data:\n");
    for (const Landmark& landmark : landmarks) {
      std::printf("  %s: [", landmark.label.c_str());
      for (std::size_t i = 0; i < kFieldCount; ++i) {
        std::printf(i ? ", %.17g" : "%.17g", landmark.values[i]);
      }
      std::printf("]\n");
    }
  }
  return 0;
}
