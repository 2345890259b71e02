// Text for people: valid UTF-8, bounded, key masked.
#include "translator/text.h"

#include <gtest/gtest.h>

#include "planner/model/json_io.h"

namespace ctb {
namespace {

TEST(Text, InvalidUtf8IsReplacedSoJsonCanBeWritten) {
  std::string lone_lead = "last read: '\xC2'";  // half of "¿": what crashed the repair request
  std::string fixed = ValidUtf8(lone_lead);
  EXPECT_EQ(fixed, "last read: '\xEF\xBF\xBD'");
  EXPECT_THROW((void)Json(lone_lead).dump(), Json::type_error);
  EXPECT_NO_THROW((void)Json(fixed).dump());
  EXPECT_EQ(ValidUtf8("\xC2\xBF"
                      "Algo m\xC3\xA1s? \xF0\x9F\x98\x8A"),
            "\xC2\xBF"
            "Algo m\xC3\xA1s? \xF0\x9F\x98\x8A");
  EXPECT_EQ(ValidUtf8("\xED\xA0\x80"), "\xEF\xBF\xBD\xEF\xBF\xBD\xEF\xBF\xBD");  // a surrogate
}

TEST(Text, CutCountsCodePointsAndNeverSplitsOne) {
  EXPECT_EQ(Cut("abc", 200), "abc");
  EXPECT_EQ(Cut(std::string(300, 'x'), 200), std::string(200, 'x') + "...");
  std::string smiles;
  for (int i = 0; i < 10; ++i) smiles += "\xF0\x9F\x98\x8A";
  std::string cut = Cut(smiles, 3);
  EXPECT_EQ(cut, "\xF0\x9F\x98\x8A\xF0\x9F\x98\x8A\xF0\x9F\x98\x8A...");
}

TEST(Text, AroundQuotesTheNeighbourhoodOfAnOffset) {
  std::string t = "{\"a\": 1,\n \"b\" 2}";
  std::string a = Around(t, t.find('2'), 5);
  EXPECT_NE(a.find("\"b\" 2}"), std::string::npos) << a;
  EXPECT_EQ(a.find('\n'), std::string::npos);
  // An offset in the middle of a multi-byte character still gives valid UTF-8.
  std::string u = "x: \xC2\xBFtrue?";
  EXPECT_EQ(ValidUtf8(Around(u, 4, 3)), Around(u, 4, 3));
}

TEST(Text, ExcerptKeepsHeadAndTailWithinTheBound) {
  std::string big = "HEAD" + std::string(100000, 'x') + "TAIL";
  std::string e = Excerpt(big, 1000);
  EXPECT_LT(e.size(), 1100u);
  EXPECT_EQ(e.rfind("HEAD", 0), 0u);
  EXPECT_NE(e.find("TAIL"), std::string::npos);
  EXPECT_NE(e.find("bytes left out"), std::string::npos);
  EXPECT_EQ(Excerpt("short", 1000), "short");
}

TEST(Text, TheKeyIsMaskedEverywhereItAppears) {
  std::string key = "sk-test-secret-key-1234";
  std::string m = MaskSecret("Incorrect API key provided: " + key + ". Bearer " + key, key);
  EXPECT_EQ(m.find(key), std::string::npos);
  EXPECT_NE(m.find("sk-...1234"), std::string::npos);
  EXPECT_EQ(MaskSecret("nothing", ""), "nothing");
  EXPECT_EQ(MaskedSecret("short"), "****");
}

}  // namespace
}  // namespace ctb
