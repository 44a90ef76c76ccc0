// Results files as an earlier ringtol wrote them, made from current ones: for the tests
// that older files still read, report and verify.
#pragma once

#include <hdf5.h>

#include <filesystem>
#include <functional>
#include <stdexcept>
#include <string>

#include "jobs/campaign/sample_record.h"

namespace ringtol::testing {

// Rewrites the results file at `path` as schema `schema` (< 4) had it: `edit` changes its
// datasets as that schema kept them, and the life outputs, which every schema before 4
// lacked, are removed. Throws std::runtime_error where HDF5 refuses.
inline void AsOlderSchema(const std::filesystem::path& path, int schema,
                          const std::function<void(hid_t)>& edit = {}) {
  const hid_t file = H5Fopen(path.c_str(), H5F_ACC_RDWR, H5P_DEFAULT);
  if (file < 0) throw std::runtime_error("AsOlderSchema: cannot open " + path.string());
  if (edit) edit(file);
  bool removed = true;
  for (std::size_t k = jobs::kFirstLifeOutput; k < jobs::kOutputCount; ++k) {
    removed = removed && H5Ldelete(file, (std::string("/outputs/") + jobs::kOutputNames[k]).c_str(), H5P_DEFAULT) >= 0;
  }
  const hid_t attribute = H5Aopen(file, "schema_version", H5P_DEFAULT);
  const bool written = attribute >= 0 && H5Awrite(attribute, H5T_NATIVE_INT, &schema) >= 0;
  if (attribute >= 0) H5Aclose(attribute);
  H5Fclose(file);
  if (!removed || !written) throw std::runtime_error("AsOlderSchema: HDF5 refused to rewrite " + path.string());
}

}  // namespace ringtol::testing
