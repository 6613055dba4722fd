// Where the shared test corpus is: $SPHEREMAP_CORPUS, else ../shared/meshes beside the
// source tree. Tests that need it call GTEST_SKIP when it is missing, so a fresh clone
// without it still passes (with those tests reported as skipped).
#pragma once

#include <cstdlib>
#include <filesystem>
#include <string>

namespace spheremap::testing {

inline std::string corpus_dir() {
  if (const char* env = std::getenv("SPHEREMAP_CORPUS")) return env;
  return SPHEREMAP_DEFAULT_CORPUS;
}

inline bool corpus_has(const std::string& name) {
  return std::filesystem::exists(corpus_dir() + "/" + name);
}

inline std::string corpus_path(const std::string& name) {
  return corpus_dir() + "/" + name;
}

}  // namespace spheremap::testing

#define SKIP_WITHOUT_CORPUS(name)                                                                  \
  if (!spheremap::testing::corpus_has(name))                                                       \
  GTEST_SKIP() << "corpus file " << (name) << " not found in " << spheremap::testing::corpus_dir() \
               << " (set SPHEREMAP_CORPUS)"
