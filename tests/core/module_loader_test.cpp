// Loading our modules (core/module_loader.hpp): where a module is looked for, the entry point of
// the first place that loads, and an error naming every place tried when none does.
#include "core/module_loader.hpp"

#include <gtest/gtest.h>
#include <unistd.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <stdexcept>
#include <string>

namespace statebench {
namespace {

namespace fs = std::filesystem;

constexpr const char* kEnv = "STATEBENCH_TEST_MODULE";

// The spec of a module that exists nowhere, unless the test points kEnv at a file.
ModuleSpec Spec(const char* build_path, const char* entry = "statebench_test_api") {
  return ModuleSpec{.file_name = "libstatebench_no_such_module.so",
                    .env_variable = kEnv,
                    .build_path = build_path,
                    .entry_point = entry,
                    .what = "the test module"};
}

class ModuleLoaderTest : public ::testing::Test {
 protected:
  void SetUp() override {
    unsetenv(kEnv);
    dir_ = fs::temp_directory_path() /
           ("statebench_module_loader_" + std::to_string(getpid()) + "_" +
            ::testing::UnitTest::GetInstance()->current_test_info()->name());
    fs::create_directories(dir_);
  }
  void TearDown() override {
    unsetenv(kEnv);
    fs::remove_all(dir_);
  }

  // The message LoadModuleEntry throws with (empty if it does not throw).
  static std::string LoadError(const ModuleSpec& spec) {
    try {
      LoadModuleEntry(spec);
    } catch (const std::runtime_error& e) {
      return e.what();
    }
    return "";
  }

  fs::path dir_;
};

TEST_F(ModuleLoaderTest, LooksBesideTheProgramThenWhereTheBuildPutIt) {
  const std::vector<fs::path> where = ModuleCandidates(Spec("/build/lib/libx.so"));
  ASSERT_EQ(where.size(), 2u);
  const fs::path exe = fs::read_symlink("/proc/self/exe");
  EXPECT_EQ(where[0], exe.parent_path().parent_path() / "lib" / "libstatebench_no_such_module.so");
  EXPECT_EQ(where[1], fs::path("/build/lib/libx.so"));
  // Without a build path, beside the program only.
  EXPECT_EQ(ModuleCandidates(Spec(nullptr)).size(), 1u);
}

TEST_F(ModuleLoaderTest, TheEnvironmentVariableIsTheOnlyPlaceTriedWhenSet) {
  setenv(kEnv, "/somewhere/libmine.so", 1);
  const std::vector<fs::path> where = ModuleCandidates(Spec("/build/lib/libx.so"));
  ASSERT_EQ(where.size(), 1u);
  EXPECT_EQ(where[0], fs::path("/somewhere/libmine.so"));
  // Set but empty: as if unset.
  setenv(kEnv, "", 1);
  EXPECT_EQ(ModuleCandidates(Spec("/build/lib/libx.so")).size(), 2u);
}

TEST_F(ModuleLoaderTest, AnErrorNamesEveryPlaceTriedAndWhy) {
  const fs::path not_a_library = dir_ / "libtext.so";
  std::ofstream(not_a_library) << "not an ELF file\n";
  const std::string why = LoadError(Spec(not_a_library.c_str()));
  EXPECT_NE(why.find("cannot load the test module libstatebench_no_such_module.so"),
            std::string::npos)
      << why;
  EXPECT_NE(why.find("set STATEBENCH_TEST_MODULE to its path"), std::string::npos) << why;
  EXPECT_NE(why.find(ModuleCandidates(Spec(nullptr))[0].string() + ": no such file"),
            std::string::npos)
      << why;
  // The loader's own message for the file that is there but is no library.
  EXPECT_NE(why.find(not_a_library.string() + ": "), std::string::npos) << why;
  EXPECT_EQ(why.find(not_a_library.string() + ": no such file"), std::string::npos) << why;
}

TEST_F(ModuleLoaderTest, ALibraryWithoutTheEntryPointIsRefused) {
  setenv(kEnv, "/lib/x86_64-linux-gnu/libm.so.6", 1);
  if (!fs::exists("/lib/x86_64-linux-gnu/libm.so.6")) GTEST_SKIP() << "no libm.so.6 there";
  const std::string why = LoadError(Spec(nullptr, "statebench_no_such_entry"));
  EXPECT_NE(why.find("libm.so.6: no statebench_no_such_entry entry point"), std::string::npos)
      << why;
}

TEST_F(ModuleLoaderTest, ReturnsTheEntryPointOfTheLibraryThatLoads) {
  setenv(kEnv, "/lib/x86_64-linux-gnu/libm.so.6", 1);
  if (!fs::exists("/lib/x86_64-linux-gnu/libm.so.6")) GTEST_SKIP() << "no libm.so.6 there";
  void* entry = LoadModuleEntry(Spec(nullptr, "cos"));
  ASSERT_NE(entry, nullptr);
  const auto cosine = reinterpret_cast<double (*)(double)>(entry);
  EXPECT_EQ(cosine(0.0), 1.0);
  EXPECT_NEAR(cosine(1.0), 0.5403023058681398, 1e-15);
}

}  // namespace
}  // namespace statebench
