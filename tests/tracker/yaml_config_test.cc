#include "arttrack/tracker/yaml_config.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

#include "../error_of.h"
#include "../scratch_dir.h"
#include "arttrack/tracker/error.h"

namespace arttrack {
namespace {
namespace fs = std::filesystem;

using test_support::error_of;

class YamlConfigTest : public ::testing::Test {
 protected:
  std::string write(const std::string& name, const std::string& text) {
    return scratch_.write(name, text).string();
  }
  const test_support::ScratchDir scratch_{"yaml_config_test"};  // one per test
  const fs::path& dir_ = scratch_.path();
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

TEST_F(YamlConfigTest, ExtendsAListMergesInOrder) {
  write("common.yaml", "a: {x: 0, z: 0}\n");
  write("first.yaml", "extends: common.yaml\na: {x: 1, y: 1}\n");
  write("second.yaml", "extends: common.yaml\na: {y: 2}\n");
  const auto f = write("child.yaml", "extends: [first.yaml, second.yaml]\na: {z: 3}\n");
  // common.yaml under both bases is no cycle.
  const YamlDocument doc = load_yaml_file(f);
  ConfigNode root = ConfigNode::root(doc);
  // second.yaml comes with its base, which sets x again over first.yaml's.
  EXPECT_EQ(root.child("a").required<int>("x"), 0);
  EXPECT_EQ(root.child("a").required<int>("y"), 2);
  EXPECT_EQ(root.child("a").required<int>("z"), 3);
  EXPECT_NO_THROW(root.finish());
  const auto empty = write("empty.yaml", "extends: []\n");
  EXPECT_NE(error_of([&] { load_yaml_file(empty); }).find("empty.yaml: key 'extends' must be"),
            std::string::npos);
}

TEST_F(YamlConfigTest, ExtendsCycleIsAnError) {
  write("a.yaml", "extends: b.yaml\n");
  const auto b = write("b.yaml", "extends: a.yaml\n");
  EXPECT_NE(error_of([&] { load_yaml_file(b); }).find("cycle"), std::string::npos);
}

TEST_F(YamlConfigTest, ExtendingAFolderIsAnError) {
  const std::string a = write("a.yaml", "extends: " + dir_.string() + "\n");
  EXPECT_NE(error_of([&] { load_yaml_file(a); }).find(dir_.string() + ": is a folder"),
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
  EXPECT_NE(error_of([&] { load_yaml_file(a); }).find("values once its aliases are expanded"),
            std::string::npos);
  EXPECT_NE(error_of([&] { load_yaml_string(text, "s.yaml"); }).find("s.yaml: more than"),
            std::string::npos);
}

TEST_F(YamlConfigTest, UnknownKeyIsNamedWithItsPathAndFile) {
  const auto f = write("c.yaml", "camera: {fovy_deg: 45, fvoy: 3}\n");
  ConfigNode root = ConfigNode::root(load_yaml_file(f));
  EXPECT_EQ(root.child("camera").required<double>("fovy_deg"), 45);
  const std::string msg = error_of([&] { root.finish(); });
  EXPECT_NE(msg.find("camera.fvoy"), std::string::npos) << msg;
  EXPECT_NE(msg.find("c.yaml"), std::string::npos) << msg;
}

TEST_F(YamlConfigTest, WrongTypeAndRangeAreNamed) {
  ConfigNode root = ConfigNode::root(load_yaml_string("rate_hz: fast\nc: 1.5\n", "t.yaml"));
  EXPECT_NE(error_of([&] { root.number("rate_hz", 1, 0, 10); }).find("'rate_hz' must be a number"),
            std::string::npos);
  EXPECT_NE(error_of([&] { root.number("c", 0.5, 0, 1); }).find("out of range"), std::string::npos);
  EXPECT_NE(error_of([&] { root.required<double>("missing"); }).find("'missing' is required"),
            std::string::npos);
}

TEST_F(YamlConfigTest, MalformedYamlNamesFileAndLine) {
  const auto f = write("bad.yaml", "a: 1\nb: [1, 2\n");
  const std::string msg = error_of([&] { load_yaml_file(f); });
  EXPECT_NE(msg.find("bad.yaml:"), std::string::npos) << msg;
  EXPECT_NE(msg.find("malformed"), std::string::npos) << msg;
  EXPECT_NE(error_of([&] { load_yaml_file((dir_ / "none.yaml").string()); }).find("not found"),
            std::string::npos);
}

// yaml-cpp keeps both entries of a duplicated key and a lookup takes one.
TEST_F(YamlConfigTest, DuplicatedKeyNamesFileKeyAndLine) {
  const auto f = write("dup.yaml", "a: 1\ncamera:\n  fovy_deg: 45\n  width: 64\n  fovy_deg: 60\n");
  const std::string msg = error_of([&] { load_yaml_file(f); });
  EXPECT_NE(msg.find("dup.yaml:5:"), std::string::npos) << msg;
  EXPECT_NE(msg.find("'camera.fovy_deg' appears twice (first at line 3)"), std::string::npos)
      << msg;
  const std::string top = error_of([&] { load_yaml_string("x: 1\ny: 2\nx: 3\n", "t.yaml"); });
  EXPECT_NE(top.find("t.yaml:3: key 'x' appears twice"), std::string::npos) << top;
  const std::string in_list =
      error_of([&] { load_yaml_string("l:\n  - {n: 1, n: 2}\n", "t.yaml"); });
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
  EXPECT_NE(error_of([&] { apply_override(doc, "novalue"); }).find("key=value"), std::string::npos);
  EXPECT_NE(error_of([&] { apply_override(doc, "encoders.bias_deg.x=1"); }).find("not a map"),
            std::string::npos);
}

// A map value merges into a map key by key, deeply (as `extends` does);
// `{}` empties it. Until stop 85 a map replaced the whole map, so
// `tracker_overrides.uncertainty.a=1` dropped a file's own `uncertainty.b`.
TEST_F(YamlConfigTest, OverridesMergeMapsIntoMaps) {
  YamlDocument doc = load_yaml_string("u: {a: 1, b: 2, n: {p: 1, q: 2}}\nl: [1]\n", "s.yaml");
  apply_override(doc, "u={a: 5, n: {p: 3}, c: 4}");
  EXPECT_EQ(find_key(doc.root, "u.a")->as<int>(), 5);
  EXPECT_EQ(find_key(doc.root, "u.b")->as<int>(), 2);
  EXPECT_EQ(find_key(doc.root, "u.c")->as<int>(), 4);
  EXPECT_EQ(find_key(doc.root, "u.n.p")->as<int>(), 3);
  EXPECT_EQ(find_key(doc.root, "u.n.q")->as<int>(), 2);
  apply_override(doc, "u.n={}");  // empties
  EXPECT_EQ(find_key(doc.root, "u.n")->size(), 0u);
  EXPECT_EQ(find_key(doc.root, "u.a")->as<int>(), 5);
  apply_override(doc, "l={x: 1}");  // a map over a list replaces it
  EXPECT_EQ(find_key(doc.root, "l.x")->as<int>(), 1);
  apply_override(doc, "u.a={y: 2}");  // and over a scalar
  EXPECT_EQ(find_key(doc.root, "u.a.y")->as<int>(), 2);
}

// Key paths: names and list indices, `a.b[1].c`, lists of lists `m[1][0]`.
TEST(KeyPath, ParsesNamesAndIndices) {
  const std::vector<KeyStep> steps = parse_key_path("a.b[1].c");
  ASSERT_EQ(steps.size(), 4u);
  EXPECT_EQ(steps[0].name, "a");
  EXPECT_EQ(steps[1].name, "b");
  EXPECT_TRUE(steps[2].is_index());
  EXPECT_EQ(steps[2].index, 1u);
  EXPECT_EQ(steps[3].name, "c");
  const std::vector<KeyStep> nested = parse_key_path("m[1][0]");
  ASSERT_EQ(nested.size(), 3u);
  EXPECT_EQ(nested[1].index, 1u);
  EXPECT_EQ(nested[2].index, 0u);
  EXPECT_FALSE(parse_key_path("duration_s")[0].is_index());
}

TEST(KeyPath, MalformedPathsAreErrorsNamingTheKey) {
  for (const char* key : {"", "a..b", "a.", ".a", "[0].x", "a[x]", "a[", "a[]", "a]", "a[0]b",
                          "a[1.5]", "a[99999999999]"}) {
    const std::string msg = error_of([&] { parse_key_path(key); });
    EXPECT_NE(msg.find(std::string("key '") + key + "'"), std::string::npos) << key << ": " << msg;
  }
  const std::string negative = error_of([&] { parse_key_path("encoders[-1].offset_deg"); });
  EXPECT_NE(negative.find("key 'encoders[-1].offset_deg' has a negative index '[-1]'"),
            std::string::npos)
      << negative;
}

constexpr char kLists[] = R"(
a: {b: [{c: 1, d: 2}, {c: 3}]}
l: [1, 2, 3]
m: [[1, 2], [3, 4]]
s: 5
)";

TEST(KeyPath, FindKeyReadsThroughMapsAndLists) {
  const YamlDocument doc = load_yaml_string(kLists, "l.yaml");
  EXPECT_EQ(find_key(doc.root, "a.b[1].c")->as<int>(), 3);
  EXPECT_EQ(find_key(doc.root, "m[1][0]")->as<int>(), 3);
  EXPECT_EQ(find_key(doc.root, "s")->as<int>(), 5);
  for (const char* missing : {"a.b[2].c", "a.b[0].x", "l[0].x", "s[0]", "a[0]", "x.y"})
    EXPECT_FALSE(find_key(doc.root, missing).has_value()) << missing;
}

TEST(KeyPath, OverridesReachListElementsAndKeepTheRest) {
  YamlDocument doc = load_yaml_string(kLists, "l.yaml");
  apply_override(doc, "a.b[1].c=9");
  apply_override(doc, "a.b[0].e.f=4");  // maps inside an element are created
  apply_override(doc, "l[2]=7");
  apply_override(doc, "m[1][0]=[5]");
  EXPECT_EQ(find_key(doc.root, "a.b[1].c")->as<int>(), 9);
  EXPECT_EQ(find_key(doc.root, "a.b[0].c")->as<int>(), 1);
  EXPECT_EQ(find_key(doc.root, "a.b[0].d")->as<int>(), 2);
  EXPECT_EQ(find_key(doc.root, "a.b[0].e.f")->as<int>(), 4);
  EXPECT_EQ(doc.root["a"]["b"].size(), 2u);
  EXPECT_EQ(doc.root["l"].as<std::vector<int>>(), (std::vector<int>{1, 2, 7}));
  EXPECT_EQ(find_key(doc.root, "m[1][0]")->as<std::vector<int>>(), std::vector<int>{5});
  EXPECT_EQ(find_key(doc.root, "m[1][1]")->as<int>(), 4);
}

TEST(KeyPath, IndexPastTheEndNamesTheKeyAndTheLength) {
  YamlDocument doc = load_yaml_string(kLists, "l.yaml");
  std::string msg = error_of([&] { apply_override(doc, "a.b[2].c=1"); });
  EXPECT_NE(msg.find("override 'a.b[2].c=1': 'a.b' has 2 element(s): no [2]"), std::string::npos)
      << msg;
  msg = error_of([&] { apply_override(doc, "m[0][5]=1"); });
  EXPECT_NE(msg.find("'m[0]' has 2 element(s): no [5]"), std::string::npos) << msg;
  // Nothing was added: a list is never grown.
  EXPECT_EQ(doc.root["a"]["b"].size(), 2u);
  EXPECT_EQ(doc.root["m"][0].size(), 2u);
}

TEST(KeyPath, IndexIntoANonListAndKeyIntoAListAreErrors) {
  YamlDocument doc = load_yaml_string(kLists, "l.yaml");
  std::string msg = error_of([&] { apply_override(doc, "a[0]=1"); });
  EXPECT_NE(msg.find("'a' is a map, not a list to index with [0]"), std::string::npos) << msg;
  msg = error_of([&] { apply_override(doc, "s[0]=1"); });
  EXPECT_NE(msg.find("'s' is '5', not a list to index with [0]"), std::string::npos) << msg;
  msg = error_of([&] { apply_override(doc, "x.y[0]=1"); });
  EXPECT_NE(msg.find("'x.y' is missing, not a list to index with [0]"), std::string::npos) << msg;
  msg = error_of([&] { apply_override(doc, "a.b.c=1"); });
  EXPECT_NE(msg.find("'a.b' is not a map (a list of 2: index it, e.g. a.b[0])"), std::string::npos)
      << msg;
  msg = error_of([&] { apply_override(doc, "l[0].x=1"); });
  EXPECT_NE(msg.find("'l[0]' is not a map"), std::string::npos) << msg;
  msg = error_of([&] { apply_override(doc, "l[-1]=1"); });
  EXPECT_NE(msg.find("override 'l[-1]=1': key 'l[-1]' has a negative index"), std::string::npos)
      << msg;
}

TEST_F(YamlConfigTest, ChoiceRejectsUnknownValue) {
  ConfigNode root = ConfigNode::root(load_yaml_string("method: fusion\n", "m.yaml"));
  const std::string msg = error_of([&] {
    root.choice("method", "full_fusion", {"full_fusion", "encoders_only"});
  });
  EXPECT_NE(msg.find("not one of"), std::string::npos) << msg;
}

}  // namespace
}  // namespace arttrack
