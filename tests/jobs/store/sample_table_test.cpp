#include "jobs/store/sample_table.h"

#include <hdf5.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <filesystem>
#include <functional>
#include <limits>
#include <stdexcept>
#include <string>
#include <vector>

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include "jobs/inputs/input_error.h"
#include "tests/support/text_files.h"

namespace ringtol::jobs::hdf5 {
namespace {

namespace fs = std::filesystem;
using ::testing::AllOf;
using ::testing::ElementsAre;
using ::testing::HasSubstr;

constexpr std::int64_t kSamples = 40;
constexpr std::int64_t kChunk = 8;  // five chunks along N
constexpr std::size_t kWidth = 3;
constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
constexpr auto kPending = static_cast<std::int8_t>(SampleStatus::kPending);
constexpr auto kOk = static_cast<std::int8_t>(SampleStatus::kOk);

fs::path TestFolder() { return ringtol::testing::FreshTestFolder("sample_table_test"); }

// Three columns: a row of kWidth numbers that finished samples must hold finite, a count,
// and the statuses.
std::vector<ColumnSpec> Specs() {
  std::vector<ColumnSpec> specs(3);
  specs[0].path = specs[0].stored_path = "/point";
  specs[0].fill = kNaN;
  specs[0].finite = FiniteRule::kWhenFinished;
  specs[1].path = specs[1].stored_path = "/count";
  specs[1].type = ColumnType::kInt32;
  specs[1].fill = -1;
  specs[2].path = specs[2].stored_path = "/status";
  specs[2].type = ColumnType::kInt8Enum;
  specs[2].enumeration = StatusType;
  specs[2].fill = kPending;
  return specs;
}

RowSpace Flat() {
  RowSpace space;
  space.samples = kSamples;
  space.chunk_samples = kChunk;
  space.extendable = true;
  return space;
}

RowSpace Grouped(std::int64_t groups) {
  RowSpace space = Flat();
  space.groups = groups;
  space.extendable = false;
  return space;
}

struct TestFile {
  Where where;
  FileId file;
};

TestFile Create(const fs::path& path, const RowSpace& space, std::vector<ColumnSpec> specs) {
  TestFile test{Where{path.string(), false}, FileId()};
  const PlistId access = FileAccess(test.where);
  test.file = FileId(H5Fcreate(path.c_str(), H5F_ACC_TRUNC, H5P_DEFAULT, access.get()));
  if (!space.grouped()) specs[0].width = kWidth;
  SampleTable::Create(test.where, test.file.get(), space, specs, true);
  return test;
}

SampleTable Open(const TestFile& test, const RowSpace& space) {
  std::vector<ColumnSpec> specs = Specs();
  if (!space.grouped()) specs[0].width = kWidth;
  return SampleTable::Open(test.where, test.file.get(), space, specs);
}

// Rows `keys`: point (k, k, k) with k the sample, count = 10 x group + sample, status ok.
void WriteRows(SampleTable& table, const std::vector<RowKey>& keys) {
  std::vector<double> points;
  std::vector<std::int32_t> counts;
  std::vector<std::int8_t> statuses;
  for (const RowKey& key : keys) {
    for (std::size_t j = 0; j < std::max<std::size_t>(1, table.spec(0).width); ++j) {
      points.push_back(static_cast<double>(key.sample));
    }
    counts.push_back(static_cast<std::int32_t>(10 * key.group + key.sample));
    statuses.push_back(kOk);
  }
  const std::array<const void*, 3> values = {points.data(), counts.data(), statuses.data()};
  table.Write(keys, values);
}

// Every test ends with every HDF5 identifier it opened closed again: the table owns its
// handles, failures included.
class SampleTableTest : public ::testing::Test {
 protected:
  void TearDown() override {
    EXPECT_EQ(H5Fget_obj_count(H5F_OBJ_ALL, H5F_OBJ_ALL), 0);
  }
};

TEST_F(SampleTableTest, AFlatTableReadsItsRunsBackAndUnwrittenRowsAsTheirFill) {
  const TestFile test = Create(TestFolder() / "flat.h5", Flat(), Specs());
  SampleTable table = Open(test, Flat());
  EXPECT_EQ(table.space().chunk_samples, kChunk);
  WriteRows(table, {{0, 3}, {0, 4}, {0, 9}});  // two runs, across a chunk boundary

  EXPECT_THAT(table.Read<std::int32_t>(1, 0, 2, 4), ElementsAre(-1, 3, 4, -1));
  const std::vector<double> points = table.Read<double>(0, 0, 9, 2);
  ASSERT_EQ(points.size(), 2 * kWidth);
  EXPECT_EQ(points[0], 9.0);
  EXPECT_TRUE(std::isnan(points[kWidth]));  // sample 10 is pending: NaN is its fill
  EXPECT_EQ(table.Pending(0, 0, 10), (std::vector<SampleRange>{{0, 3}, {5, 9}}));
}

// A campaign of 2^40 samples: only what was written is read, wherever the writes landed,
// so that opening, scanning and listing its pending samples take no longer than for 40.
TEST_F(SampleTableTest, AFlatTableOfTwoToTheFortyRowsReadsNoFurtherThanItsFarthestChunk) {
  constexpr std::int64_t kHuge = std::int64_t{1} << 40;
  RowSpace huge = Flat();
  huge.samples = kHuge;
  const TestFile test = Create(TestFolder() / "huge.h5", huge, Specs());
  {
    SampleTable table = Open(test, huge);
    EXPECT_EQ(table.written_end(), 0);
    EXPECT_EQ(table.Pending(0, 0, kHuge), (std::vector<SampleRange>{{0, kHuge}}));
    WriteRows(table, {{0, 3 * kChunk + 1}});  // the farthest chunk first
    WriteRows(table, {{0, 1}});
    EXPECT_EQ(table.written_end(), 4 * kChunk);
  }
  const SampleTable table = Open(test, huge);  // found again in the chunk indexes
  EXPECT_EQ(table.written_end(), 4 * kChunk);
  const std::vector<SampleRange> rest = {{0, 1}, {2, 3 * kChunk + 1}, {3 * kChunk + 2, kHuge}};
  EXPECT_EQ(table.Pending(0, 0, kHuge), rest);
  EXPECT_EQ(table.Finished(), (std::vector<SampleRange>{{1, 2}, {3 * kChunk + 1, 3 * kChunk + 2}}));
  const TableScan scan = table.Scan();
  EXPECT_TRUE(scan.damaged.empty());
  EXPECT_EQ(scan.done, 2);
  EXPECT_EQ(scan.pending, rest);
}

TEST_F(SampleTableTest, AGroupedTableKeepsEachGroupsRowApartAndScansOnlyChunksThatExist) {
  const TestFile test = Create(TestFolder() / "grouped.h5", Grouped(4), Specs());
  SampleTable table = Open(test, Grouped(4));
  WriteRows(table, {{1, 0}, {1, 1}, {3, 0}});

  EXPECT_THAT(table.Read<std::int32_t>(1, 1, 0, 3), ElementsAre(10, 11, -1));
  EXPECT_THAT(table.Read<std::int32_t>(1, 3, 0, 2), ElementsAre(30, -1));
  EXPECT_THAT(table.Read<std::int32_t>(1, 2, 0, 2), ElementsAre(-1, -1));
  const TableScan scan = table.Scan();
  EXPECT_TRUE(scan.damaged.empty());
  EXPECT_EQ(scan.done, 3);
  EXPECT_TRUE(scan.pending.empty());  // a grouped table does not list its unsimulated rows
  hsize_t chunks = 0;
  const DatasetId status(H5Dopen2(test.file.get(), "/status", H5P_DEFAULT));
  const SpaceId space(H5Dget_space(status.get()));
  H5Dget_num_chunks(status.get(), space.get(), &chunks);
  EXPECT_EQ(chunks, 2u);  // one chunk each of candidates 1 and 3: nothing for the others
}

TEST_F(SampleTableTest, AFinishedRowHoldingANonFiniteNumberIsDamageThatRepairMakesPending) {
  const TestFile test = Create(TestFolder() / "finite.h5", Flat(), Specs());
  SampleTable table = Open(test, Flat());
  WriteRows(table, {{0, 17}, {0, 18}});
  // Sample 18's point becomes NaN behind the table's back (a file without checksums).
  const std::vector<double> nan(kWidth, kNaN);
  const std::int32_t count = 18;
  const std::array<const void*, 3> row = {nan.data(), &count, &kOk};
  table.Write(std::vector<RowKey>{{0, 18}}, row);
  const std::string message = ringtol::testing::MessageOf<InputError>([&] { table.Read<double>(0, 0, 16, 4); });
  EXPECT_THAT(message, AllOf(HasSubstr("dataset /point is damaged"), HasSubstr("sample 18 is ok"),
                             HasSubstr("ringtol verify")));

  const TableScan scan = table.Scan();
  ASSERT_EQ(scan.damaged.size(), 1u);
  EXPECT_EQ(scan.damaged[0].column, 0u);
  EXPECT_EQ(scan.damaged[0].samples, (SampleRange{16, 24}));  // the whole chunk
  EXPECT_EQ(scan.done, 2);

  table.Repair(scan.damaged);
  EXPECT_EQ(table.Pending(0, 16, 24), (std::vector<SampleRange>{{16, 24}}));  // sample 17 too: its chunk is computed again
  EXPECT_TRUE(table.Scan().damaged.empty());
}

TEST_F(SampleTableTest, AColumnTheFileLacksReadsAsItsFillAndGrowKeepsWhatIsWritten) {
  const TestFile test = Create(TestFolder() / "grow.h5", Flat(), Specs());
  {
    SampleTable table = Open(test, Flat());
    WriteRows(table, {{0, kSamples - 1}});
    table.Grow(2 * kSamples);
    EXPECT_EQ(table.space().samples, 2 * kSamples);
  }
  std::vector<ColumnSpec> specs = Specs();
  specs[0].width = kWidth;
  specs[1].stored_path.clear();  // as a file of an older schema
  RowSpace space = Flat();
  space.samples = 2 * kSamples;
  const SampleTable table = SampleTable::Open(test.where, test.file.get(), space, specs);
  EXPECT_FALSE(table.stored(1));
  EXPECT_THAT(table.Read<std::int32_t>(1, 0, kSamples - 1, 2), ElementsAre(-1, -1));
  EXPECT_THAT(table.Statuses(0, kSamples - 1, 2), ElementsAre(SampleStatus::kOk, SampleStatus::kPending));
}

TEST_F(SampleTableTest, ReadingAColumnAsAnotherTypeIsTheCallersMistake) {
  const TestFile test = Create(TestFolder() / "types.h5", Flat(), Specs());
  SampleTable table = Open(test, Flat());
  EXPECT_THROW(table.Read<double>(1, 0, 0, 1), std::logic_error);
  EXPECT_THROW(table.Read<float>(0, 0, 0, 1), std::logic_error);
  EXPECT_THROW(table.Read<std::int32_t>(1, 0, kSamples, 1), std::out_of_range);
}

TEST(RowBuffer, TheLastRowOfAKeyWinsAndOverlaysTheFilesValues) {
  RowBuffer<double> buffer;
  buffer.Put({1, 2}, 5.0);
  buffer.Put({0, 3}, 7.0);
  buffer.Put({1, 2}, 6.0);
  EXPECT_EQ(buffer.size(), 2u);
  EXPECT_EQ(buffer.Keys(), (std::vector<RowKey>{{0, 3}, {1, 2}}));
  std::vector<double> row = {0.0, 0.0, 0.0};
  buffer.Overlay(1, 1, 4, row, [](double value) { return value; });
  EXPECT_EQ(row, (std::vector<double>{0.0, 6.0, 0.0}));
}

TEST(RegularRuns, BlocksAtEqualSpacingAreOneStridedRunAndOddOnesRunsOfTheirOwn) {
  // Block-cyclic blocks of 8 over 3 ranks, then a half block and an adopted pair of blocks.
  const std::vector<SampleRange> rows = {{8, 16}, {32, 40}, {56, 64}, {80, 84}, {100, 108}, {124, 132}};
  EXPECT_EQ(RegularRuns(rows), (std::vector<StridedRows>{{8, 24, 3, 8}, {80, 4, 1, 4}, {100, 24, 2, 8}}));
  EXPECT_EQ(RegularRuns(std::vector<SampleRange>{{5, 6}}), (std::vector<StridedRows>{{5, 1, 1, 1}}));
  EXPECT_TRUE(RegularRuns(std::vector<SampleRange>{}).empty());
  // A row that breaks the spacing starts a new run, which the next rows may extend.
  EXPECT_EQ(RegularRuns(std::vector<SampleRange>{{0, 2}, {10, 12}, {15, 17}, {20, 22}}),
            (std::vector<StridedRows>{{0, 10, 2, 2}, {15, 5, 2, 2}}));
}

}  // namespace
}  // namespace ringtol::jobs::hdf5
