// shell_quote: every byte but NUL survives a trip through bash and POSIX sh exactly, and
// nothing in a quoted word (quotes, $(...), backquotes, newlines) is run.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "blocks/base/input_error.h"
#include "blocks/base/shell_quote.h"
#include "testbench/lib/cli_harness.h"
#include "testbench/lib/temp_dir.h"

namespace texsim {
namespace {

using cli_harness::shell;
using cli_harness::slurp;

std::vector<std::string> hostile_words() {
  std::vector<std::string> w = {"q'$(touch PWNED)'",
                                "`touch PWNED`",
                                "$(touch PWNED)",
                                "a\nb\n\ntouch PWNED\n",
                                "\"$HOME\" \"",
                                "back\\slash\\",
                                "two  spaces ",
                                "",
                                "'",
                                "''",
                                "'\\''",
                                "-n",
                                "--out=x;touch PWNED",
                                "!$ !! ${x:-y} ~ * ? [a] #",
                                "\r\t\x1b[31m"};
  std::string all;
  for (int b = 1; b < 256; ++b) all += static_cast<char>(b);
  w.push_back(all);
  for (int b = 1; b < 256; ++b) w.emplace_back(1, static_cast<char>(b));
  return w;
}

TEST(ShellQuote, SingleQuotesWithEscapedQuotes) {
  EXPECT_EQ(shell_quote(""), "''");
  EXPECT_EQ(shell_quote("a b"), "'a b'");
  EXPECT_EQ(shell_quote("it's"), "'it'\\''s'");
  EXPECT_EQ(shell_quote("$x`y`\n"), "'$x`y`\n'");
}

TEST(ShellQuote, NulIsRefused) {
  try {
    (void)shell_quote(std::string("a\0b", 3), "--out");
    FAIL() << "a NUL byte was quoted";
  } catch (const InputError& e) {
    EXPECT_EQ(std::string(e.what()), "--out: contains a NUL byte, which no shell word can hold");
  }
}

// Each word written by shell_quote into a script `printf '%s\0' WORD...`, run by bash and by
// sh in a scratch directory: the words come back byte for byte and no PWNED file appears.
TEST(ShellQuote, HostileWordsRoundTripThroughBashAndSh) {
  const std::vector<std::string> words = hostile_words();
  TempDir d("shell_quote");
  std::string script = "printf '%s\\0'", expected;
  for (const std::string& w : words) {
    script.append(" ").append(shell_quote(w));
    expected.append(w).push_back('\0');
  }
  std::ofstream(d.file("words.sh"), std::ios::binary) << script << " > out\n";
  for (const char* sh : {"bash", "sh"}) {
    std::string command = "cd ";
    command.append(shell_quote(d.file(""))).append(" && ").append(sh).append(" words.sh");
    const auto r = shell(command);
    ASSERT_EQ(r.code, 0) << sh << ": " << r.out;
    const std::string got = slurp(d.file("out"));
    EXPECT_EQ(got, expected) << sh;
    EXPECT_FALSE(std::filesystem::exists(d.file("PWNED"))) << sh;
    EXPECT_EQ(d.entries(), 2u) << sh;  // words.sh and out: nothing else was created
  }
}

}  // namespace
}  // namespace texsim
