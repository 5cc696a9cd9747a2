// Taking every sample a CycloneDDS reader holds, loaned (no copy out of its buffers), for the
// readers of the DDS layer whose listeners hand each sample on. Internal to src/dds.
// Thread-safety: as dds_take's (a reader's listener, or its owner's thread).
#pragma once

#include <dds/dds.h>

#include <cstdint>

namespace keel::dds {

/// Calls `each(sample, info)` for every sample `reader` holds (invalid ones too: a disposal's
/// info), then returns the loans. Nothing `each` throws may leave a C callback: it must not.
template <class Each>
void takeAll(dds_entity_t reader, Each&& each) {
  constexpr std::uint32_t kBatch = 16;
  void* samples[kBatch];
  dds_sample_info_t infos[kBatch];
  for (;;) {
    samples[0] = nullptr;  // loaned
    const dds_return_t n = dds_take(reader, samples, infos, kBatch, kBatch);
    if (n <= 0) break;
    for (dds_return_t i = 0; i < n; ++i) each(samples[i], infos[i]);
    dds_return_loan(reader, samples, n);
  }
}

}  // namespace keel::dds
