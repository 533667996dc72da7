// apps::CsvTable: the text written is the header and the rows as given, numbers as printf
// prints them; rows of the wrong width are refused, and a file that cannot be written whole
// is an error naming it (a full disk included), never a short file.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "ndtom_apps/csv_table.h"
#include "support/thrown_message.h"

using ndtom::apps::CsvCell;
using ndtom::apps::CsvTable;
using ndtom::testing::thrownMessage;

TEST(CsvTable, TextIsTheHeaderAndTheRows) {
  CsvTable table({"name", "count", "value", "fixed"});
  table.addRow({"a", 3, 0.1, CsvCell::formatted("%.6f", 2.5)});
  table.addRow({std::string("b"), size_t(4), int64_t(-5), ""});
  EXPECT_EQ(table.text(), "name,count,value,fixed\na,3,0.1,2.500000\nb,4,-5,\n");
  EXPECT_EQ(table.numRows(), 2u);
  EXPECT_EQ(CsvCell(1.0 / 3).text, "0.3333333333");  // 10 significant digits
  EXPECT_EQ(CsvCell::formatted("%g", 1.0 / 3).text, "0.333333");
}

TEST(CsvTable, RowsOfTheWrongWidthAreRefused) {
  CsvTable table({"a", "b"});
  EXPECT_THROW(table.addRow({1}), std::logic_error);
  EXPECT_THROW(table.addRow({1, 2, 3}), std::logic_error);
  EXPECT_EQ(table.numRows(), 0u);
}

TEST(CsvTable, ColumnsAsNumbers) {
  CsvTable table({"x", "label"});
  table.addRow({1.5, "p"});
  table.addRow({"", "q"});
  const std::vector<double> x = table.column("x");
  ASSERT_EQ(x.size(), 2u);
  EXPECT_EQ(x[0], 1.5);
  EXPECT_TRUE(std::isnan(x[1]));
  EXPECT_TRUE(std::isnan(table.column("label")[0]));
  EXPECT_THROW(table.column("y"), std::logic_error);
}

TEST(CsvTable, WritesTheText) {
  CsvTable table({"a"});
  table.addRow({7});
  const std::string path = ::testing::TempDir() + "/csv_table_test.csv";
  table.write(path);
  std::stringstream read;
  read << std::ifstream(path).rdbuf();
  EXPECT_EQ(read.str(), table.text());
  std::filesystem::remove(path);
}

TEST(CsvTable, AFailedWriteNamesTheFile) {
  CsvTable table({"a"});
  table.addRow({"x"});
  EXPECT_EQ(thrownMessage([&] { table.write("/nonexistent/folder/t.csv"); }),
            "cannot write /nonexistent/folder/t.csv: No such file or directory");
  if (!std::filesystem::exists("/dev/full")) GTEST_SKIP() << "no /dev/full";
  EXPECT_EQ(thrownMessage([&] { table.write("/dev/full"); }),
            "cannot write /dev/full: No space left on device");
}
