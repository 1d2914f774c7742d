// The shared study writer: CSV and Markdown from one table, and labelled plot series.
#include <gtest/gtest.h>

#include "pipeline/studies/study_table.h"

namespace texsim {
namespace {

TEST(StudyTable, WritesCsvAndMarkdown) {
  StudyTable t({"method", "cycles"}, "lr");
  t.add({"ewa", "14.7"});
  t.add({"\"a, b\"", ""});
  EXPECT_EQ(t.size(), 2u);
  EXPECT_EQ(t.csv(), "method,cycles\newa,14.7\n\"a, b\",\n");
  EXPECT_EQ(t.markdown(), "| method | cycles |\n|---|---:|\n| ewa | 14.7 |\n| \"a, b\" |  |\n");
}

// Names with commas (relief methods, terrain deformations, header cells) stay one cell.
TEST(StudyTable, CsvQuotesCellsWithCommasQuotesOrLineBreaks) {
  StudyTable t({"reads, exact", "method"});
  t.add({"offset parallax, limited", "say \"hi\""});
  t.add({"two\nlines", "\"already, quoted\""});
  EXPECT_EQ(t.csv(),
            "\"reads, exact\",method\n\"offset parallax, limited\",\"say \"\"hi\"\"\"\n"
            "\"two\nlines\",\"already, quoted\"\n");
  EXPECT_EQ(t.markdown(),
            "| reads, exact | method |\n|---|---|\n| offset parallax, limited | say \"hi\" |\n"
            "| two\nlines | \"already, quoted\" |\n");
}

TEST(StudyTable, LabelledSeriesKeepsEveryPointsLabel) {
  const PlotSeries s = labelled_series("ewa", {{1, 2, "a"}, {3, 4, "b"}});
  EXPECT_EQ(s.label, "ewa");
  EXPECT_EQ(s.x, (std::vector<double>{1, 3}));
  EXPECT_EQ(s.y, (std::vector<double>{2, 4}));
  EXPECT_EQ(s.point_labels, (std::vector<std::string>{"a", "b"}));
  EXPECT_FALSE(s.lines);
}

}  // namespace
}  // namespace texsim
