// The simulator's internal text helpers (sim/src/text_format.h), whose
// behaviour the CSV, HTML and YAML outputs depend on byte for byte:
//   - csv_field quotes only on ',', '"' or '\n' and doubles quotes;
//   - csv_number round-trips doubles and spells non-finite values;
//   - format_g is printf "%.*g";
//   - html_escape escapes & < > " and nothing else;
//   - base64 is RFC 4648's;
//   - trim, parse_number, one_line, write_text, median_convergence_s.
#include "../../sim/src/text_format.h"

#include <gtest/gtest.h>

#include <unistd.h>
#include <cmath>
#include <cstdlib>
#include <fstream>
#include <limits>
#include <sstream>
#include <vector>

#include "arttrack/tracker/error.h"

namespace arttrack::sim {
namespace {

namespace fs = std::filesystem;
constexpr double kInf = std::numeric_limits<double>::infinity();
constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

TEST(TextFormat, CsvFieldQuotesOnlyCommasQuotesAndNewlines) {
  EXPECT_EQ(text::csv_field(""), "");
  EXPECT_EQ(text::csv_field("plain text"), "plain text");
  EXPECT_EQ(text::csv_field(" padded "), " padded ");
  EXPECT_EQ(text::csv_field("carriage\rreturn"), "carriage\rreturn");
  EXPECT_EQ(text::csv_field("a,b"), "\"a,b\"");
  EXPECT_EQ(text::csv_field("line\nbreak"), "\"line\nbreak\"");
  EXPECT_EQ(text::csv_field("say \"hi\""), "\"say \"\"hi\"\"\"");
  EXPECT_EQ(text::csv_field("\""), "\"\"\"\"");
}

TEST(TextFormat, CsvNumberRoundTripsAndSpellsNonFiniteValues) {
  EXPECT_EQ(text::csv_number(0), "0");
  EXPECT_EQ(text::csv_number(-0.0), "-0");
  EXPECT_EQ(text::csv_number(1.5), "1.5");
  EXPECT_EQ(text::csv_number(0.1), "0.10000000000000001");
  EXPECT_EQ(text::csv_number(1e300), "1.0000000000000001e+300");
  EXPECT_EQ(text::csv_number(kNaN), "nan");
  EXPECT_EQ(text::csv_number(-kNaN), "nan");
  EXPECT_EQ(text::csv_number(kInf), "inf");
  EXPECT_EQ(text::csv_number(-kInf), "-inf");
  for (double v : {0.1, 1.0 / 3.0, -2.718281828459045, 6.02214076e23, 4.9e-324,
                   std::numeric_limits<double>::max(), -std::numeric_limits<double>::min()})
    EXPECT_EQ(std::strtod(text::csv_number(v).c_str(), nullptr), v) << text::csv_number(v);
}

TEST(TextFormat, FormatGIsPrintfG) {
  EXPECT_EQ(text::format_g(0.1, 3), "0.1");
  EXPECT_EQ(text::format_g(1234567, 3), "1.23e+06");
  EXPECT_EQ(text::format_g(123456, 6), "123456");
  EXPECT_EQ(text::format_g(0.0001234, 3), "0.000123");
  EXPECT_EQ(text::format_g(0.00001234, 3), "1.23e-05");
  EXPECT_EQ(text::format_g(2.5, 1), "2");  // round half to even
  EXPECT_EQ(text::format_g(0.1 + 0.2, 12), "0.3");
  EXPECT_EQ(text::format_g(-0.0, 6), "-0");
  EXPECT_EQ(text::format_g(kInf, 6), "inf");
  EXPECT_EQ(text::format_g(-kInf, 6), "-inf");
  EXPECT_EQ(text::format_g(kNaN, 6), "nan");
  EXPECT_EQ(text::format_g(-std::numeric_limits<double>::max(), 17), "-1.7976931348623157e+308");
}

TEST(TextFormat, HtmlEscapeEscapesAmpersandAnglesAndDoubleQuotesOnly) {
  EXPECT_EQ(text::html_escape(""), "");
  EXPECT_EQ(text::html_escape("a < b && c > \"d\""), "a &lt; b &amp;&amp; c &gt; &quot;d&quot;");
  EXPECT_EQ(text::html_escape("it's"), "it's");
  EXPECT_EQ(text::html_escape("&amp;"), "&amp;amp;");
  EXPECT_EQ(text::html_escape("\xc2\xb0 deg\n"), "\xc2\xb0 deg\n");
}

TEST(TextFormat, Base64KnownVectorsAndAlphabet) {
  // RFC 4648, section 10: every padding case.
  const std::pair<std::string, std::string> vectors[] = {{"", ""},
                                                         {"f", "Zg=="},
                                                         {"fo", "Zm8="},
                                                         {"foo", "Zm9v"},
                                                         {"foob", "Zm9vYg=="},
                                                         {"fooba", "Zm9vYmE="},
                                                         {"foobar", "Zm9vYmFy"}};
  for (const auto& [in, out] : vectors)
    EXPECT_EQ(text::base64({reinterpret_cast<const std::uint8_t*>(in.data()), in.size()}), out);
  // The 48 bytes whose 6-bit groups count 0 to 63 encode as the alphabet.
  std::vector<std::uint8_t> bytes(48, 0);
  for (int i = 0; i < 64; ++i)
    for (int bit = 0; bit < 6; ++bit)
      if (i >> (5 - bit) & 1) bytes[(i * 6 + bit) / 8] |= std::uint8_t(0x80 >> ((i * 6 + bit) % 8));
  EXPECT_EQ(text::base64(bytes),
            "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/");
  for (std::size_t n = 0; n < 10; ++n)
    EXPECT_EQ(text::base64(std::vector<std::uint8_t>(n, 0xff)).size(), (n + 2) / 3 * 4);
}

TEST(TextFormat, TrimAndParseNumber) {
  EXPECT_EQ(text::trim("  a b\t"), "a b");
  EXPECT_EQ(text::trim(" \t "), "");
  EXPECT_EQ(text::trim("x\r\n"), "x\r\n");
  double v = 0;
  EXPECT_TRUE(text::parse_number(" 2.5\t", v));
  EXPECT_EQ(v, 2.5);
  EXPECT_TRUE(text::parse_number("-1e-3", v));
  EXPECT_EQ(v, -1e-3);
  v = 7;
  EXPECT_FALSE(text::parse_number("   ", v));
  EXPECT_EQ(v, 7);  // untouched when blank
  EXPECT_FALSE(text::parse_number("1.5x", v));
  EXPECT_FALSE(text::parse_number("1 2", v));
  EXPECT_FALSE(text::parse_number("inf", v));
  EXPECT_FALSE(text::parse_number("nan", v));
  EXPECT_FALSE(text::parse_number("1e999", v));
}

TEST(TextFormat, OneLineReplacesLineBreaksAndTabsBySpaces) {
  EXPECT_EQ(text::one_line("a\nb\r\nc\td"), "a b  c d");
  EXPECT_EQ(text::one_line("plain"), "plain");
}

TEST(TextFormat, WriteTextWritesBytesAndNamesTheFileOnFailure) {
  const fs::path dir =
      fs::temp_directory_path() / ("text_format_test_" + std::to_string(::getpid()));
  fs::create_directories(dir);
  const fs::path file = dir / "out.txt";
  text::write_text(file, "old contents, longer\n");
  text::write_text(file, "a\r\nb\n");
  std::ifstream in(file, std::ios::binary);
  std::stringstream s;
  s << in.rdbuf();
  EXPECT_EQ(s.str(), "a\r\nb\n");
  const fs::path bad = dir / "no_such_dir" / "out.txt";
  try {
    text::write_text(bad, "x");
    ADD_FAILURE() << "no error";
  } catch (const InputError& e) {
    EXPECT_EQ(std::string(e.what()), bad.string() + ": cannot write file");
  }
  fs::remove_all(dir);
}

TEST(TextFormat, MedianConvergenceCountsNeverAsInfinity) {
  MethodSummary s;
  EXPECT_EQ(median_convergence_s(s), kInf);
  s.time_to_converge_s = {3.0, std::nullopt, 1.0};
  EXPECT_EQ(median_convergence_s(s), 3.0);
  s.time_to_converge_s = {4.0, 2.0};
  EXPECT_EQ(median_convergence_s(s), 3.0);
  s.time_to_converge_s = {2.0, std::nullopt};
  EXPECT_EQ(median_convergence_s(s), kInf);
  s.time_to_converge_s = {std::nullopt};
  EXPECT_EQ(median_convergence_s(s), kInf);
}

}  // namespace
}  // namespace arttrack::sim
