#include "arttrack/tracker/yaml_config.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

#include "arttrack/tracker/error.h"

namespace arttrack {
namespace {
namespace fs = std::filesystem;

std::string message_of(const std::function<void()>& f) {
  try {
    f();
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

class YamlConfigTest : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() /
           ("arttrack_yaml_" + std::to_string(::testing::UnitTest::GetInstance()->random_seed()) +
            ::testing::UnitTest::GetInstance()->current_test_info()->name());
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }
  std::string write(const std::string& name, const std::string& text) {
    const auto p = dir_ / name;
    std::ofstream(p) << text;
    return p.string();
  }
  fs::path dir_;
};

TEST_F(YamlConfigTest, ExtendsMergesMapsDeeplyAndChildWins) {
  write("base.yaml", "a: {x: 1, y: 2}\nlist: [1, 2, 3]\nname: base\n");
  const auto f = write("child.yaml", "extends: base.yaml\na: {y: 5}\nlist: [9]\n");
  const YamlDocument doc = load_yaml_file(f);
  ConfigNode root = ConfigNode::root(doc);
  EXPECT_EQ(root.child("a").required<int>("x"), 1);
  EXPECT_EQ(root.child("a").required<int>("y"), 5);
  EXPECT_EQ(root.required<std::vector<int>>("list"), std::vector<int>{9});
  EXPECT_EQ(root.required<std::string>("name"), "base");
  EXPECT_NO_THROW(root.finish());
}

TEST_F(YamlConfigTest, ExtendsCycleIsAnError) {
  write("a.yaml", "extends: b.yaml\n");
  const auto b = write("b.yaml", "extends: a.yaml\n");
  EXPECT_NE(message_of([&] { load_yaml_file(b); }).find("cycle"), std::string::npos);
}

TEST_F(YamlConfigTest, ExtendingAFolderIsAnError) {
  const std::string a = write("a.yaml", "extends: " + dir_.string() + "\n");
  EXPECT_NE(message_of([&] { load_yaml_file(a); }).find(dir_.string() + ": is a folder"),
            std::string::npos);
}

// Aliases of aliases expand exponentially (here to 1e9 values in 500
// bytes): refused after kMaxYamlValues, not walked for minutes.
TEST_F(YamlConfigTest, AliasBombIsRefused) {
  std::string text = "a0: &a0 [x, x, x, x, x, x, x, x, x, x]\n";
  for (int i = 1; i < 9; ++i) {
    text += "a" + std::to_string(i) + ": &a" + std::to_string(i) + " [";
    for (int k = 0; k < 10; ++k) text += (k ? ", *a" : "*a") + std::to_string(i - 1);
    text += "]\n";
  }
  const std::string a = write("a.yaml", text);
  EXPECT_NE(message_of([&] { load_yaml_file(a); }).find("values once its aliases are expanded"),
            std::string::npos);
  EXPECT_NE(message_of([&] { load_yaml_string(text, "s.yaml"); }).find("s.yaml: more than"),
            std::string::npos);
}

TEST_F(YamlConfigTest, UnknownKeyIsNamedWithItsPathAndFile) {
  const auto f = write("c.yaml", "camera: {fovy_deg: 45, fvoy: 3}\n");
  ConfigNode root = ConfigNode::root(load_yaml_file(f));
  EXPECT_EQ(root.child("camera").required<double>("fovy_deg"), 45);
  const std::string msg = message_of([&] { root.finish(); });
  EXPECT_NE(msg.find("camera.fvoy"), std::string::npos) << msg;
  EXPECT_NE(msg.find("c.yaml"), std::string::npos) << msg;
}

TEST_F(YamlConfigTest, WrongTypeAndRangeAreNamed) {
  ConfigNode root = ConfigNode::root(load_yaml_string("rate_hz: fast\nc: 1.5\n", "t.yaml"));
  EXPECT_NE(
      message_of([&] { root.number("rate_hz", 1, 0, 10); }).find("'rate_hz' must be a number"),
      std::string::npos);
  EXPECT_NE(message_of([&] { root.number("c", 0.5, 0, 1); }).find("out of range"),
            std::string::npos);
  EXPECT_NE(message_of([&] { root.required<double>("missing"); }).find("'missing' is required"),
            std::string::npos);
}

TEST_F(YamlConfigTest, MalformedYamlNamesFileAndLine) {
  const auto f = write("bad.yaml", "a: 1\nb: [1, 2\n");
  const std::string msg = message_of([&] { load_yaml_file(f); });
  EXPECT_NE(msg.find("bad.yaml:"), std::string::npos) << msg;
  EXPECT_NE(msg.find("malformed"), std::string::npos) << msg;
  EXPECT_NE(message_of([&] { load_yaml_file((dir_ / "none.yaml").string()); }).find("not found"),
            std::string::npos);
}

// yaml-cpp keeps both entries of a duplicated key and a lookup takes one.
TEST_F(YamlConfigTest, DuplicatedKeyNamesFileKeyAndLine) {
  const auto f = write("dup.yaml", "a: 1\ncamera:\n  fovy_deg: 45\n  width: 64\n  fovy_deg: 60\n");
  const std::string msg = message_of([&] { load_yaml_file(f); });
  EXPECT_NE(msg.find("dup.yaml:5:"), std::string::npos) << msg;
  EXPECT_NE(msg.find("'camera.fovy_deg' appears twice (first at line 3)"), std::string::npos)
      << msg;
  const std::string top = message_of([&] { load_yaml_string("x: 1\ny: 2\nx: 3\n", "t.yaml"); });
  EXPECT_NE(top.find("t.yaml:3: key 'x' appears twice"), std::string::npos) << top;
  const std::string in_list =
      message_of([&] { load_yaml_string("l:\n  - {n: 1, n: 2}\n", "t.yaml"); });
  EXPECT_NE(in_list.find("'l[0].n'"), std::string::npos) << in_list;
}

TEST_F(YamlConfigTest, OverridesCreateAndReplaceKeys) {
  YamlDocument doc = load_yaml_string("encoders: {bias_deg: 1}\n", "s.yaml");
  apply_override(doc, "encoders.bias_deg=5");
  apply_override(doc, "camera.delay_s=0.1");
  apply_override(doc, "list=[1, 2]");
  ConfigNode root = ConfigNode::root(doc);
  EXPECT_EQ(root.child("encoders").required<double>("bias_deg"), 5);
  EXPECT_EQ(root.child("camera").required<double>("delay_s"), 0.1);
  EXPECT_EQ(root.required<std::vector<int>>("list").size(), 2u);
  EXPECT_NE(message_of([&] { apply_override(doc, "novalue"); }).find("key=value"),
            std::string::npos);
  EXPECT_NE(message_of([&] { apply_override(doc, "encoders.bias_deg.x=1"); }).find("not a map"),
            std::string::npos);
}

TEST_F(YamlConfigTest, ChoiceRejectsUnknownValue) {
  ConfigNode root = ConfigNode::root(load_yaml_string("method: fusion\n", "m.yaml"));
  const std::string msg = message_of([&] {
    root.choice("method", "full_fusion", {"full_fusion", "encoders_only"});
  });
  EXPECT_NE(msg.find("not one of"), std::string::npos) << msg;
}

}  // namespace
}  // namespace arttrack
