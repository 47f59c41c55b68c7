// Escaping user text for messages (math/user_text.h): every control character and every byte
// that is not UTF-8 becomes visible, other text is kept, and escaping twice changes nothing.
#include "math/user_text.h"

#include <gtest/gtest.h>

#include <random>
#include <string>

namespace anamorph {
namespace {

using namespace std::string_literals;

TEST(Printable, EscapesControlCharactersAndKeepsText) {
  EXPECT_EQ(printable("camera.fov"), "camera.fov");
  EXPECT_EQ(printable("a\x1b[31mred"), "a\\x1b[31mred");
  EXPECT_EQ(printable("line\nnext\r\ttab"), "line\\nnext\\r\\ttab");
  EXPECT_EQ(printable("nul\0here"s), "nul\\x00here");
  EXPECT_EQ(printable("del\x7f"), "del\\x7f");
  EXPECT_EQ(printable("csi\xc2\x9b"
                      "2J"),
            "csi\\u009b2J");  // C1 CSI as UTF-8
  EXPECT_EQ(printable("raw\x9b"
                      "2J"),
            "raw\\x9b2J");                                           // a lone byte: not UTF-8
  EXPECT_EQ(printable("caf\xc3\xa9 \xe2\x82\xac \xf0\x9f\x8e\xa5"),  // é € 🎥 stay
            "caf\xc3\xa9 \xe2\x82\xac \xf0\x9f\x8e\xa5");
  EXPECT_EQ(printable("\xc0\xaf"), "\\xc0\\xaf");           // overlong '/'
  EXPECT_EQ(printable("\xed\xa0\x80"), "\\xed\\xa0\\x80");  // a surrogate
  EXPECT_EQ(printable("back\\slash"), "back\\slash");
}

TEST(Printable, OutputHasNoControlBytesAndEscapingAgainChangesNothing) {
  std::mt19937 rng(7);
  for (int n = 0; n < 2000; ++n) {
    std::string s(size_t(rng() % 24), '\0');
    for (char& c : s) c = char(rng() % 256);
    const std::string once = printable(s), twice = printable(once);
    EXPECT_EQ(once, twice) << "input bytes: " << once;
    for (size_t i = 0; i < once.size(); ++i) {
      const auto c = static_cast<unsigned char>(once[i]);
      EXPECT_FALSE(c < 0x20 || c == 0x7f) << "control byte " << int(c) << " in " << twice;
      if (c == 0xC2 && i + 1 < once.size()) {
        EXPECT_GE(static_cast<unsigned char>(once[i + 1]), 0xA0) << "C1 control in " << twice;
      }
    }
  }
}

TEST(NulInPath, IsFoundAndNamedWithWhatTheSystemWouldRead) {
  EXPECT_FALSE(has_nul("scene.toml"));
  EXPECT_TRUE(has_nul("scene.toml\0junk"s));
  EXPECT_EQ(nul_in_path_message("tex.png\0x"s),
            "the file name 'tex.png\\x00x' contains a NUL character (the system would read it as "
            "'tex.png')");
  EXPECT_EQ(nul_in_path_message("a\0b"s, false),
            "the file name contains a NUL character (the system would read it as 'a')");
}

}  // namespace
}  // namespace anamorph
