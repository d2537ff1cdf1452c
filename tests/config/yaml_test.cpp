// Strict YAML files: a key written twice in one mapping is refused with both lines named,
// at any depth, while the same key in different mappings stays allowed; a key that is not a
// plain word is refused with its line (it once escaped as a yaml-cpp exception: fuzz_model).
#include <gtest/gtest.h>

#include <string>

#include "core/config/yaml.h"
#include "tests/support/refusal.h"

namespace enact::config {
namespace {

// the message load_file refuses `text` with ("" when it loads)
std::string refusal_of(const std::string& text) {
  return test::error_of_file("f.yaml", text, [](const std::string& path) { load_file(path); });
}

TEST(StrictYaml, DuplicateTopLevelKeyNamesBothLines) {
  const std::string err = refusal_of("name: a\nperiod_ns: 1000\nname: b\n");
  EXPECT_NE(err.find("f.yaml:3:"), std::string::npos) << err;
  EXPECT_NE(err.find("duplicate key 'name'"), std::string::npos) << err;
  EXPECT_NE(err.find("first on line 1"), std::string::npos) << err;
  EXPECT_NE(err.find("fix:"), std::string::npos) << err;
}

TEST(StrictYaml, DuplicateKeyInsideListOfMappings) {
  const std::string err = refusal_of("masses:\n  - name: m1\n    mass_kg: 1\n  - name: m2\n    mass_kg: 1\n    mass_kg: 2\n");
  EXPECT_NE(err.find("f.yaml:6:"), std::string::npos) << err;
  EXPECT_NE(err.find("duplicate key 'mass_kg' (first on line 5)"), std::string::npos) << err;
}

TEST(StrictYaml, DuplicateKeyInFlowMapping) {
  const std::string err = refusal_of("params: {a: 1, b: 2, a: 3}\n");
  EXPECT_NE(err.find("duplicate key 'a' (first on line 1)"), std::string::npos) << err;
}

TEST(StrictYaml, SameKeyInSeparateMappingsIsAllowed) {
  EXPECT_EQ(refusal_of("a:\n  name: x\nb:\n  name: y\nlist:\n  - name: p\n  - name: q\n"), "");
}

TEST(StrictYaml, AliasedMappingIsAcceptedAndCheckedOnce) {
  EXPECT_EQ(refusal_of("base: &b {k: 1, j: 2}\nx: *b\ny: *b\n"), "");
}

TEST(StrictYaml, KeyThatIsAListIsRefusedWithItsLine) {
  const std::string err = test::error_of_file("f.yaml", "name: a\n[x, y]: 1\n", [](const std::string& path) {
    Map(load_file(path), path, "scene", {"name"});
  });
  EXPECT_NE(err.find("f.yaml:2:"), std::string::npos) << err;
  EXPECT_NE(err.find("a key in scene must be a single word"), std::string::npos) << err;
}

}  // namespace
}  // namespace enact::config
