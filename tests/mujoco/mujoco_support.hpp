#pragma once
// Loading MJCF text into MuJoCo for the tests of grip::mujoco.
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <memory>
#include <string>

#include <unistd.h>

#include <mujoco/mujoco.h>

namespace grip_test {

struct ModelDeleter {
  void operator()(mjModel* m) const { mj_deleteModel(m); }
};
struct DataDeleter {
  void operator()(mjData* d) const { mj_deleteData(d); }
};
using ModelPtr = std::unique_ptr<mjModel, ModelDeleter>;
using DataPtr = std::unique_ptr<mjData, DataDeleter>;

/// Loads MJCF text (written to a temporary file: MuJoCo 2.2 reads files); `error` gets
/// MuJoCo's message when it fails.
inline ModelPtr load_mjcf(const std::string& xml, std::string* error = nullptr) {
  static int counter = 0;
  const std::filesystem::path path =
      std::filesystem::temp_directory_path() /
      ("grip_mujoco_test_" + std::to_string(::getpid()) + "_" + std::to_string(counter++) + ".xml");
  {
    std::ofstream out(path);
    out << xml;
  }
  char buf[1000] = "";
  mjModel* m = mj_loadXML(path.string().c_str(), nullptr, buf, sizeof buf);
  std::filesystem::remove(path);
  if (error) *error = buf;
  return ModelPtr(m);
}

}  // namespace grip_test
