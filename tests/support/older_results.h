// Results files as an earlier ringtol wrote them, made from current ones: for the tests
// that older files still read, report and verify.
#pragma once

#include <hdf5.h>

#include <algorithm>
#include <cstdint>
#include <filesystem>
#include <functional>
#include <stdexcept>
#include <string>
#include <vector>

#include "jobs/campaign/sample_record.h"

namespace ringtol::testing {

// Rewrites the results file at `path` as schema `schema` (< 6) had it: no off-bore shares
// and roller names; below 5, a message per sample in /outputs/message instead of the
// failure rows, no draw checksums; `edit` changes its datasets as that schema kept them,
// and below schema 4 the life outputs, which every schema before 4 lacked, are removed.
// Throws std::runtime_error where HDF5 refuses. The file must keep every sample's inputs
// (fewer than kStoredInputSamples).
inline void AsOlderSchema(const std::filesystem::path& path, int schema,
                          const std::function<void(hid_t)>& edit = {}) {
  const hid_t file = H5Fopen(path.c_str(), H5F_ACC_RDWR, H5P_DEFAULT);
  if (file < 0) throw std::runtime_error("AsOlderSchema: cannot open " + path.string());
  bool done = H5Ldelete(file, "/outputs/off_bore_percent", H5P_DEFAULT) >= 0 &&
              H5Ldelete(file, "/rollers", H5P_DEFAULT) >= 0;
  if (schema < 5) {
    constexpr std::size_t kMessageBytes = 256;
    const hid_t text = H5Tcopy(H5T_C_S1);
    H5Tset_size(text, kMessageBytes);
    H5Tset_strpad(text, H5T_STR_NULLTERM);
    H5Tset_cset(text, H5T_CSET_UTF8);  // as ringtol writes its text
    const hid_t samples = H5Dopen2(file, "/failures/sample", H5P_DEFAULT);
    const hid_t messages = H5Dopen2(file, "/failures/message", H5P_DEFAULT);
    const hid_t space = H5Dget_space(samples);
    const auto failures = static_cast<std::size_t>(H5Sget_simple_extent_npoints(space));
    std::vector<std::int64_t> failed(failures);
    std::vector<char> texts(failures * kMessageBytes);
    if (failures > 0) {
      done = done && H5Dread(samples, H5T_NATIVE_INT64, H5S_ALL, H5S_ALL, H5P_DEFAULT, failed.data()) >= 0;
      done = done && H5Dread(messages, text, H5S_ALL, H5S_ALL, H5P_DEFAULT, texts.data()) >= 0;
    }
    H5Sclose(space);
    H5Dclose(messages);
    H5Dclose(samples);
    std::int64_t n = 0;
    const hid_t attribute = H5Aopen(file, "samples", H5P_DEFAULT);
    done = done && attribute >= 0 && H5Aread(attribute, H5T_NATIVE_INT64, &n) >= 0;
    H5Aclose(attribute);
    std::vector<char> per_sample(static_cast<std::size_t>(n) * kMessageBytes, '\0');
    for (std::size_t i = 0; i < failures; ++i) {
      std::copy_n(texts.begin() + static_cast<std::ptrdiff_t>(i * kMessageBytes), kMessageBytes,
                  per_sample.begin() + static_cast<std::ptrdiff_t>(failed[i]) * static_cast<std::ptrdiff_t>(kMessageBytes));
    }
    const hsize_t dims[1] = {static_cast<hsize_t>(n)};
    const hsize_t max_dims[1] = {H5S_UNLIMITED};
    const hid_t column_space = H5Screate_simple(1, dims, max_dims);
    const hid_t dcpl = H5Pcreate(H5P_DATASET_CREATE);
    H5Pset_chunk(dcpl, 1, dims);
    H5Pset_fletcher32(dcpl);
    const hid_t column =
        H5Dcreate2(file, "/outputs/message", text, column_space, H5P_DEFAULT, dcpl, H5P_DEFAULT);
    done = done && column >= 0 && H5Dwrite(column, text, H5S_ALL, H5S_ALL, H5P_DEFAULT, per_sample.data()) >= 0;
    H5Dclose(column);
    H5Pclose(dcpl);
    H5Sclose(column_space);
    H5Tclose(text);
    done = done && H5Ldelete(file, "/failures", H5P_DEFAULT) >= 0;
    done = done && H5Ldelete(file, "/inputs/draw_checksum", H5P_DEFAULT) >= 0;
    done = done && H5Adelete(file, "inputs_stored_below") >= 0;
  }
  if (edit) edit(file);
  for (std::size_t k = 0; k < jobs::kOutputCount; ++k) {
    if (!jobs::IsLifeOutput(k) || schema >= jobs::kOutputs[k].first_schema) continue;
    done = done && H5Ldelete(file, (std::string("/outputs/") + jobs::kOutputNames[k]).c_str(), H5P_DEFAULT) >= 0;
  }
  const hid_t attribute = H5Aopen(file, "schema_version", H5P_DEFAULT);
  const bool written = attribute >= 0 && H5Awrite(attribute, H5T_NATIVE_INT, &schema) >= 0;
  if (attribute >= 0) H5Aclose(attribute);
  H5Fclose(file);
  if (!done || !written) throw std::runtime_error("AsOlderSchema: HDF5 refused to rewrite " + path.string());
}

}  // namespace ringtol::testing
