// What HDF5's virtual datasets (the serial libhdf5 ringtol links) cost for a results file
// assembled from the shards of K ranks instead of joined (docs/results.md, "Shards"): one
// float64 column of N samples whose stored chunks of `rows` samples were written by the
// ranks in turn (block-cyclically, jobs/pool/block_schedule.h), mapped four ways:
//   interleaved  one mapping per shard, selecting its chunks' rows as a union of blocks
//                (an irregular hyperslab)
//   strided      one mapping per shard, its chunks' rows as one regular strided hyperslab
//                on both sides, plus one for a last, shorter chunk
//   per-run      one mapping per chunk (a single block each)
//   contiguous   one mapping per shard of one block (as if each rank computed one range)
// Times creating the virtual dataset, opening it, reading the column twice (the first read
// opens every shard) and 1,000 reads of one random row.
//
// Built with -DRINGTOL_BENCHMARKS=ON (build/tests/ringtol_virtual_dataset_costs), or alone:
//   g++ -std=c++20 -O2 tests/benchmarks/virtual_dataset_costs.cpp -I/usr/include/hdf5/serial -lhdf5_serial -o vds_costs
//   vds_costs FOLDER SHARDS SAMPLES ROWS interleaved|strided|per-run|contiguous
//
// FOLDER must exist and is filled with the shards and vds.h5; the numbers are wall times.
#include <hdf5.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <random>
#include <string>
#include <vector>

namespace {

double Seconds(std::chrono::steady_clock::time_point since) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - since).count();
}

std::string ShardName(int shard) { return "vds.h5.shard-" + std::to_string(shard); }

// Chunk b of the column was written by shard b mod K (contiguous: shard b / (chunks / K)).
int Writer(hsize_t chunk, hsize_t chunks, int shards, bool contiguous) {
  if (!contiguous) return static_cast<int>(chunk % static_cast<hsize_t>(shards));
  const hsize_t per_shard = (chunks + static_cast<hsize_t>(shards) - 1) / static_cast<hsize_t>(shards);
  return static_cast<int>(chunk / per_shard);
}

}  // namespace

int main(int argc, char** argv) {
  if (argc != 6) {
    std::fprintf(stderr, "usage: %s FOLDER SHARDS SAMPLES ROWS interleaved|strided|per-run|contiguous\n", argv[0]);
    return 2;
  }
  const std::string folder = argv[1];
  const int shards = std::atoi(argv[2]);
  const auto samples = static_cast<hsize_t>(std::atoll(argv[3]));
  const auto rows = static_cast<hsize_t>(std::atoll(argv[4]));
  const std::string layout = argv[5];
  const bool contiguous = layout == "contiguous";
  const bool per_run = layout == "per-run";
  const bool strided = layout == "strided";
  const hsize_t chunks = (samples + rows - 1) / rows;
  const hsize_t dims[1] = {samples};
  const hsize_t chunk_dims[1] = {rows};
  const hid_t fapl = H5Pcreate(H5P_FILE_ACCESS);
  H5Pset_libver_bounds(fapl, H5F_LIBVER_LATEST, H5F_LIBVER_LATEST);

  // The shards: each a full-size chunked, checksummed column holding only its chunks.
  auto start = std::chrono::steady_clock::now();
  std::vector<double> values(rows);
  for (int shard = 0; shard < shards; ++shard) {
    const hid_t file = H5Fcreate((folder + "/" + ShardName(shard)).c_str(), H5F_ACC_TRUNC, H5P_DEFAULT, fapl);
    const hid_t space = H5Screate_simple(1, dims, nullptr);
    const hid_t dcpl = H5Pcreate(H5P_DATASET_CREATE);
    H5Pset_chunk(dcpl, 1, chunk_dims);
    H5Pset_fletcher32(dcpl);
    const hid_t dataset = H5Dcreate2(file, "x", H5T_IEEE_F64LE, space, H5P_DEFAULT, dcpl, H5P_DEFAULT);
    for (hsize_t chunk = 0; chunk < chunks; ++chunk) {
      if (Writer(chunk, chunks, shards, contiguous) != shard) continue;
      const hsize_t first[1] = {chunk * rows};
      const hsize_t count[1] = {std::min(rows, samples - chunk * rows)};
      for (hsize_t i = 0; i < count[0]; ++i) values[i] = static_cast<double>(first[0] + i);
      const hid_t memory = H5Screate_simple(1, count, nullptr);
      H5Sselect_hyperslab(space, H5S_SELECT_SET, first, nullptr, count, nullptr);
      H5Dwrite(dataset, H5T_NATIVE_DOUBLE, memory, space, H5P_DEFAULT, values.data());
      H5Sclose(memory);
    }
    H5Dclose(dataset);
    H5Pclose(dcpl);
    H5Sclose(space);
    H5Fclose(file);
  }
  const double write_shards = Seconds(start);

  start = std::chrono::steady_clock::now();
  const hid_t file = H5Fcreate((folder + "/vds.h5").c_str(), H5F_ACC_TRUNC, H5P_DEFAULT, fapl);
  const hid_t space = H5Screate_simple(1, dims, nullptr);
  const hid_t dcpl = H5Pcreate(H5P_DATASET_CREATE);
  std::size_t mappings = 0;
  const hid_t selection = H5Screate_simple(1, dims, nullptr);
  for (int shard = 0; shard < shards && strided; ++shard) {
    // Chunks shard, shard + K, ...: the whole ones as one strided selection, a last shorter
    // one as a block of its own.
    const std::string name = ShardName(shard);
    const hsize_t whole = samples / rows;
    const auto k = static_cast<hsize_t>(shards);
    const auto s = static_cast<hsize_t>(shard);
    const hsize_t count[1] = {whole > s ? (whole - s + k - 1) / k : 0};
    if (count[0] > 0) {
      const hsize_t first[1] = {s * rows};
      const hsize_t stride[1] = {k * rows};
      const hsize_t block[1] = {rows};
      H5Sselect_hyperslab(selection, H5S_SELECT_SET, first, stride, count, block);
      H5Pset_virtual(dcpl, selection, name.c_str(), "x", selection);
      ++mappings;
    }
    if (samples % rows != 0 && whole % k == s) {
      const hsize_t first[1] = {whole * rows};
      const hsize_t last[1] = {samples % rows};
      H5Sselect_hyperslab(selection, H5S_SELECT_SET, first, nullptr, last, nullptr);
      H5Pset_virtual(dcpl, selection, name.c_str(), "x", selection);
      ++mappings;
    }
  }
  for (int shard = 0; shard < shards && !strided; ++shard) {
    const std::string name = ShardName(shard);
    bool any = false;
    for (hsize_t chunk = 0; chunk < chunks; ++chunk) {
      if (Writer(chunk, chunks, shards, contiguous) != shard) continue;
      const hsize_t first[1] = {chunk * rows};
      const hsize_t count[1] = {std::min(rows, samples - chunk * rows)};
      // Consecutive chunks of one shard make one block (contiguous: one per shard).
      H5Sselect_hyperslab(selection, any && !per_run ? H5S_SELECT_OR : H5S_SELECT_SET, first, nullptr, count, nullptr);
      any = true;
      if (per_run) {
        H5Pset_virtual(dcpl, selection, name.c_str(), "x", selection);
        ++mappings;
      }
    }
    if (any && !per_run) {
      H5Pset_virtual(dcpl, selection, name.c_str(), "x", selection);
      ++mappings;
    }
  }
  const hid_t created = H5Dcreate2(file, "x", H5T_IEEE_F64LE, space, H5P_DEFAULT, dcpl, H5P_DEFAULT);
  H5Dclose(created);
  H5Fclose(file);
  const double create = Seconds(start);

  start = std::chrono::steady_clock::now();
  const hid_t reading = H5Fopen((folder + "/vds.h5").c_str(), H5F_ACC_RDONLY, fapl);
  const hid_t dataset = H5Dopen2(reading, "x", H5P_DEFAULT);
  const double open = Seconds(start);
  std::vector<double> all(samples);
  start = std::chrono::steady_clock::now();
  H5Dread(dataset, H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, H5P_DEFAULT, all.data());
  const double first_read = Seconds(start);
  start = std::chrono::steady_clock::now();
  H5Dread(dataset, H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, H5P_DEFAULT, all.data());
  const double second_read = Seconds(start);
  std::size_t wrong = 0;
  for (hsize_t i = 0; i < samples; ++i) {
    if (all[i] != static_cast<double>(i)) ++wrong;
  }

  constexpr int kRowReads = 1000;
  std::mt19937_64 random(1);
  const hsize_t one[1] = {1};
  const hid_t row_memory = H5Screate_simple(1, one, nullptr);
  double value = 0.0;
  start = std::chrono::steady_clock::now();
  for (int i = 0; i < kRowReads; ++i) {
    const hsize_t first[1] = {random() % samples};
    H5Sselect_hyperslab(space, H5S_SELECT_SET, first, nullptr, one, nullptr);
    H5Dread(dataset, H5T_NATIVE_DOUBLE, row_memory, space, H5P_DEFAULT, &value);
  }
  const double row_reads = Seconds(start);
  std::printf(
      "%s: %d shards, %llu samples in chunks of %llu, %zu mappings: shards written %.3f s, virtual dataset created "
      "%.4f s, opened %.4f s, read whole %.4f s (again %.4f s, %zu wrong), one row %.1f us\n",
      layout.c_str(), shards, static_cast<unsigned long long>(samples), static_cast<unsigned long long>(rows), mappings,
      write_shards, create, open, first_read, second_read, wrong, 1e6 * row_reads / kRowReads);
  H5Sclose(row_memory);
  H5Dclose(dataset);
  H5Fclose(reading);
  H5Sclose(selection);
  H5Sclose(space);
  H5Pclose(dcpl);
  H5Pclose(fapl);
  return wrong == 0 ? 0 : 1;
}
