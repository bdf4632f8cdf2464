// Tests of net/lrs_config.cpp: file and environment, which wins, and clear errors.
#include "net/lrs_config.hpp"

#include <gtest/gtest.h>
#include <stdlib.h>
#include <sys/stat.h>

#include <filesystem>
#include <fstream>

namespace acdr {
namespace {

class LrsConfigTest : public ::testing::Test {
 protected:
  void SetUp() override {
    for (const char* name :
         {"ACDR_LRS_CONFIG", "ACDR_LRS_ENDPOINT", "ACDR_LRS_KEY", "ACDR_LRS_SECRET",
          "ACDR_XAPI_IRI_BASE", "ACDR_LRS_SEND_AFTER_ATTEMPT"}) {
      unsetenv(name);
    }
    dir_ = std::filesystem::temp_directory_path() /
           ("acdr-lrs-config-" + std::to_string(getpid()) + "-" +
            ::testing::UnitTest::GetInstance()->current_test_info()->name());
    std::filesystem::create_directories(dir_ / "config/acdr");
    setenv("XDG_CONFIG_HOME", (dir_ / "config").c_str(), 1);
  }
  void TearDown() override { std::filesystem::remove_all(dir_); }

  std::string write(const std::string& name, const std::string& text, mode_t mode = 0600) {
    const std::string path = (dir_ / name).string();
    std::filesystem::create_directories(std::filesystem::path(path).parent_path());
    std::ofstream(path) << text;
    chmod(path.c_str(), mode);
    return path;
  }

  std::filesystem::path dir_;
};

TEST_F(LrsConfigTest, NothingConfiguredIsNotAnError) {
  const LrsConfigLoad load = load_lrs_config();
  ASSERT_TRUE(load.ok()) << load.error;
  EXPECT_FALSE(load.config.has_endpoint());
  EXPECT_TRUE(load.config.activity_iri_base.empty());
}

TEST_F(LrsConfigTest, ReadsTheXdgFileAndTheEnvironmentWinsKeyByKey) {
  write("config/acdr/lrs.json",
        R"({"endpoint": "https://lrs.example.org/xapi", "key": "k", "secret": "s",
            "activity_iri_base": "https://training.example.org/acdr/",
            "send_after_attempt": true, "timeout_s": 12})");
  LrsConfigLoad load = load_lrs_config();
  ASSERT_TRUE(load.ok()) << load.error;
  EXPECT_EQ(load.config.endpoint, "https://lrs.example.org/xapi/");  // final slash added
  EXPECT_EQ(load.config.key, "k");
  EXPECT_EQ(load.config.secret, "s");
  EXPECT_EQ(load.config.activity_iri_base, "https://training.example.org/acdr/");
  EXPECT_TRUE(load.config.send_after_attempt);
  EXPECT_EQ(load.config.timeout_s, 12.0);

  setenv("ACDR_LRS_SECRET", "from-env", 1);
  setenv("ACDR_XAPI_IRI_BASE", "https://other.example.org/", 1);
  load = load_lrs_config();
  ASSERT_TRUE(load.ok()) << load.error;
  EXPECT_EQ(load.config.secret, "from-env");
  EXPECT_EQ(load.config.key, "k");
  EXPECT_EQ(load.config.activity_iri_base, "https://other.example.org/");
  EXPECT_NE(load.config.source.find("environment"), std::string::npos);
}

TEST_F(LrsConfigTest, TheEnvironmentAloneIsEnough) {
  setenv("ACDR_LRS_ENDPOINT", "http://127.0.0.1:8080/xapi/", 1);
  setenv("ACDR_LRS_KEY", "k", 1);
  setenv("ACDR_LRS_SECRET", "s", 1);
  const LrsConfigLoad load = load_lrs_config();
  ASSERT_TRUE(load.ok()) << load.error;
  EXPECT_EQ(load.config.endpoint, "http://127.0.0.1:8080/xapi/");
  EXPECT_EQ(load.config.source, "environment");
}

TEST_F(LrsConfigTest, ASecretOthersCanReadIsRefused) {
  const std::string path = write("lrs.json", R"({"endpoint": "https://lrs.example.org/",
      "key": "k", "secret": "s"})",
                                 0644);
  const LrsConfigLoad load = load_lrs_config(path);
  ASSERT_FALSE(load.ok());
  EXPECT_NE(load.error.find(path), std::string::npos) << load.error;
  EXPECT_NE(load.error.find("chmod 600"), std::string::npos) << load.error;
  // Without the secret in it, the file may be readable (the secret comes from elsewhere).
  const std::string open = write("open.json", R"({"endpoint": "https://lrs.example.org/"})", 0644);
  EXPECT_TRUE(load_lrs_config(open).ok());
}

TEST_F(LrsConfigTest, BadValuesAreNamedWithTheFile) {
  struct Case {
    const char* json;
    const char* expected;
  };
  for (const Case& c : {
           Case{R"({"endpoint": "ftp://lrs.example.org/"})", "http:// or https://"},
           Case{R"({"endpoint": "https://user:pw@lrs.example.org/"})", "not in the URL"},
           Case{R"({"endpoint": "https://lrs.example.org/?x=1"})", "query"},
           Case{R"({"endpoint": "https://lrs.example.org/", "key": "k"})", "both key and secret"},
           Case{R"({"activity_iri_base": "acdr"})", "absolute http"},
           Case{R"({"send_after_attempt": true})", "no endpoint"},
           Case{R"({"timeout_s": -1})", "timeout_s"},
           Case{R"({"endpont": "https://lrs.example.org/"})", "unknown key \"endpont\""},
           Case{R"([1, 2])", "JSON object"},
           Case{R"({"endpoint": )", "not valid JSON"},
       }) {
    const std::string path = write("bad.json", c.json);
    const LrsConfigLoad load = load_lrs_config(path);
    ASSERT_FALSE(load.ok()) << c.json;
    EXPECT_NE(load.error.find(path), std::string::npos) << load.error;
    EXPECT_NE(load.error.find(c.expected), std::string::npos) << load.error;
  }
  EXPECT_NE(load_lrs_config((dir_ / "missing.json").string()).error.find("no such"),
            std::string::npos);
  setenv("ACDR_LRS_SEND_AFTER_ATTEMPT", "maybe", 1);
  EXPECT_NE(load_lrs_config().error.find("ACDR_LRS_SEND_AFTER_ATTEMPT='maybe'"), std::string::npos);
}

}  // namespace
}  // namespace acdr
