// The simulator's internal text helpers (internal/text_format.h of sim/evaluation), whose
// behaviour the CSV, HTML and YAML outputs depend on byte for byte:
//   - csv_field quotes only on ',', '"' or '\n' and doubles quotes;
//   - csv_number round-trips doubles and spells non-finite values;
//   - format_g is printf "%.*g";
//   - html_escape escapes & < > " and nothing else;
//   - base64 is RFC 4648's;
//   - split_csv and CsvReader read back what csv_field writes, and trim
//     people's files;
//   - trim, parse_number, one_line, write_text, median_convergence_s.
#include "arttrack/sim/internal/text_format.h"

#include <gtest/gtest.h>

#include <unistd.h>
#include <cmath>
#include <cstdlib>
#include <fstream>
#include <limits>
#include <sstream>
#include <vector>

#include "../error_of.h"
#include "../scratch_dir.h"
#include "arttrack/tracker/error.h"

namespace arttrack::sim {
namespace {

namespace fs = std::filesystem;
using test_support::error_of;
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
  EXPECT_EQ(text::trim("\r x \r"), "x");
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
  EXPECT_TRUE(text::parse_number("3\r", v));
  EXPECT_EQ(v, 3);
}

TEST(TextFormat, ParseNumberOrNonFiniteAcceptsNanAndInfinities) {
  double v = 0;
  EXPECT_TRUE(text::parse_number_or_non_finite(" 2.5 ", v));
  EXPECT_EQ(v, 2.5);
  EXPECT_TRUE(text::parse_number_or_non_finite("nan", v));
  EXPECT_TRUE(std::isnan(v));
  EXPECT_TRUE(text::parse_number_or_non_finite("NaN", v));
  EXPECT_TRUE(std::isnan(v));
  EXPECT_TRUE(text::parse_number_or_non_finite("inf", v));
  EXPECT_EQ(v, kInf);
  EXPECT_TRUE(text::parse_number_or_non_finite("-inf", v));
  EXPECT_EQ(v, -kInf);
  EXPECT_TRUE(text::parse_number_or_non_finite("Infinity", v));
  EXPECT_EQ(v, kInf);
  // What csv_number writes reads back.
  for (double x : {kInf, -kInf, 0.1, -1e300}) {
    EXPECT_TRUE(text::parse_number_or_non_finite(text::csv_number(x), v));
    EXPECT_EQ(v, x);
  }
  EXPECT_FALSE(text::parse_number_or_non_finite("1e999", v));
  EXPECT_FALSE(text::parse_number_or_non_finite("-1e999", v));
  EXPECT_FALSE(text::parse_number_or_non_finite("", v));
  EXPECT_FALSE(text::parse_number_or_non_finite("nan x", v));
}

std::vector<std::string> split(const std::string& line, text::CsvSpace space) {
  const auto f = text::split_csv(line, space);
  EXPECT_TRUE(f.has_value()) << line;
  return f.value_or(std::vector<std::string>{});
}

using Fields = std::vector<std::string>;

TEST(TextFormat, SplitCsvKeepsEmptyFieldsAndUnquotes) {
  for (auto space : {text::CsvSpace::kTrim, text::CsvSpace::kVerbatim}) {
    EXPECT_EQ(split("", space), Fields{""});
    EXPECT_EQ(split("a,b", space), (Fields{"a", "b"}));
    EXPECT_EQ(split(",a,,", space), (Fields{"", "a", "", ""}));
    EXPECT_EQ(split("\"a,b\",\"say \"\"hi\"\"\",\"\"", space), (Fields{"a,b", "say \"hi\"", ""}));
    EXPECT_FALSE(text::split_csv("a,\"b", space).has_value());
    EXPECT_FALSE(text::split_csv("\"a\"\"", space).has_value());
  }
  // Whatever csv_field writes reads back, byte for byte, verbatim.
  const Fields fields = {" padded ", "a,b", "say \"hi\"", "", "tab\there", "cr\r"};
  std::string line;
  for (const std::string& f : fields) line += text::csv_field(f) + ',';
  line.pop_back();
  EXPECT_EQ(split(line, text::CsvSpace::kVerbatim), fields);
}

TEST(TextFormat, SplitCsvTrimsOutsideQuotesOnly) {
  EXPECT_EQ(split(" a , b\t,\tc d \r", text::CsvSpace::kTrim), (Fields{"a", "b", "c d"}));
  EXPECT_EQ(split(" \" a \" , ", text::CsvSpace::kTrim), (Fields{" a ", ""}));
  EXPECT_EQ(split(" a , b", text::CsvSpace::kVerbatim), (Fields{" a ", " b"}));
}

TEST(TextFormat, CsvReaderReadsRowsWithLineNumbersAndCrlfEndings) {
  const test_support::ScratchDir scratch("text_format_csv");
  const fs::path& dir = scratch.path();
  const fs::path file = dir / "in.csv";
  text::write_text(file,
                   "time_s, x ,name\r\n\r\n  \r\n0.5,nan,\"a,b\"\r\n1,inf,\r\n2,abc,c\n3,4\n");
  text::CsvReader csv(file, text::CsvSpace::kTrim);
  Fields header, row;
  ASSERT_TRUE(csv.next(header));
  EXPECT_EQ(header, (Fields{"time_s", "x", "name"}));
  EXPECT_EQ(csv.where(), file.string() + ":1");
  ASSERT_TRUE(csv.next(row));  // blank lines 2 and 3 skipped
  EXPECT_EQ(csv.where(), file.string() + ":4");
  EXPECT_EQ(row, (Fields{"0.5", "nan", "a,b"}));
  EXPECT_EQ(csv.finite(row, 0, header), 0.5);
  EXPECT_TRUE(std::isnan(csv.number(row, 1, header)));
  EXPECT_EQ(error_of([&] { csv.finite(row, 1, header); }),
            file.string() + ":4: column 'x' is not finite");
  ASSERT_TRUE(csv.next(row));
  EXPECT_EQ(row, (Fields{"1", "inf", ""}));  // the '\r' is not part of the last field
  EXPECT_EQ(csv.number(row, 1, header), kInf);
  ASSERT_TRUE(csv.next(row));
  EXPECT_EQ(error_of([&] { csv.number(row, 1, header); }),
            file.string() + ":6: column 'x': 'abc' is not a number");
  ASSERT_TRUE(csv.next(row));
  EXPECT_EQ(error_of([&] { csv.expect_width(row, header.size()); }),
            file.string() + ":7: has 2 fields, the header has 3");
  EXPECT_FALSE(csv.next(row));

  text::write_text(file, "a\n\"open,b\n");
  text::CsvReader open_quote(file, text::CsvSpace::kVerbatim);
  ASSERT_TRUE(open_quote.next(row));
  EXPECT_EQ(error_of([&] { open_quote.next(row); }), file.string() + ":2: a quote is not closed");
  EXPECT_EQ(error_of([&] { text::CsvReader(dir / "missing.csv", text::CsvSpace::kTrim); }),
            (dir / "missing.csv").string() + ": cannot read file");
}

TEST(TextFormat, OneLineReplacesLineBreaksAndTabsBySpaces) {
  EXPECT_EQ(text::one_line("a\nb\r\nc\td"), "a b  c d");
  EXPECT_EQ(text::one_line("plain"), "plain");
}

TEST(TextFormat, WriteTextWritesBytesAndNamesTheFileOnFailure) {
  const test_support::ScratchDir scratch("text_format_test");
  const fs::path& dir = scratch.path();
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
