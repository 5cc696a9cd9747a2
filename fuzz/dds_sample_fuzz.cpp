// libFuzzer target for the DDS samples keel's subscriptions receive from the network (src/dds,
// docs/dds.md): the input's first byte selects a message type (fuzz/dds_sample.hpp, byte % 8); the
// rest is a serialized sample as it arrives in a DATA submessage, its 4-byte CDR header first
// (plain CDR1 or CDR2, either byte order). CycloneDDS builds its serdata from those bytes as its
// receive thread does (ddsi_serdata_from_ser_iov: it validates and normalizes the CDR, or refuses
// it) and converts it to the C sample a reader takes (ddsi_serdata_to_sample); keel's registered
// receive path (DdsType::deliver: fromDds into the port type, sent on a connection) turns that
// into the keel::msg value.
// Checked on every sample CycloneDDS accepts, beyond no crash, leak or UB in keel's code: exactly
// one value arrives; keel's toDds of it serializes to the very bytes CycloneDDS serializes the C
// sample it received to (fromDds then toDds loses nothing and adds nothing); and those bytes, read
// again, arrive as a value that serializes to them once more.
// Thread-safety: one input at a time, as libFuzzer calls it (CycloneDDS runs threads of its own).
#include <dds/ddsi/ddsi_cdrstream.h>
#include <dds/ddsi/ddsi_serdata.h>
#include <dds/ddsi/ddsi_sertype.h>

#include <algorithm>
#include <bit>
#include <cstddef>
#include <cstdint>
#include <vector>

#include "dds_sample.hpp"

namespace {

using keel::fuzz::SampleType;

/// Whether `bytes` hit CycloneDDS 0.10's known XCDR2 bug (docs/fuzzing.md, "What it found"): its
/// normalization checks an 8-byte value or array element of CDR2 data for 4 bytes only, so a
/// sample cut short in one is byte-swapped past its end (big-endian: even if it is then refused)
/// and, accepted, read up to 4 bytes per element past its end. Found by normalizing a copy with
/// room to spare, as the receive thread would (the header's options give the padding: bit 1
/// only, as CycloneDDS reads it): a byte written beyond the sample, or a sample accepted longer
/// than it is. Such an input is not run: it would only find that bug again.
bool overrunsInCyclone(const SampleType& t, const std::uint8_t* bytes, std::size_t size) {
  if (size < 4 || bytes[0] != 0 || (bytes[1] != 0x06 && bytes[1] != 0x07)) return false;  // CDR2 BE, LE
  const std::uint32_t pad = bytes[3] & 2u;
  if (size - 4 < pad) return false;
  const auto body = static_cast<std::uint32_t>(size - 4 - pad);
  std::vector<std::uint8_t> copy(2 * std::size_t{body} + 8);  // an element over-runs by < its size
  std::copy(bytes + 4, bytes + 4 + body, copy.begin());
  for (std::size_t i = body; i < copy.size(); ++i) copy[i] = static_cast<std::uint8_t>(i * 7 + 13);
  const std::vector<std::uint8_t> before(copy.begin() + body, copy.end());
  const bool swap = (bytes[1] == 0x06) != (std::endian::native == std::endian::big);
  std::uint32_t actual = 0;
  const bool accepted = dds_stream_normalize(copy.data(), body, swap, 2,
                                             reinterpret_cast<const ddsi_sertype_default*>(t.sertype), false, &actual);
  return (accepted && actual > body) || !std::equal(before.begin(), before.end(), copy.begin() + body);
}

/// CycloneDDS's C sample of `bytes` (a CDR header and the sample) as its reader takes it, or null
/// if CycloneDDS refuses the bytes. Free with ddsi_sertype_free_sample(..., DDS_FREE_ALL).
void* receive(const SampleType& t, const std::uint8_t* bytes, std::size_t size) {
  ddsrt_iovec_t iov{};
  iov.iov_base = const_cast<std::uint8_t*>(bytes);
  iov.iov_len = static_cast<ddsrt_iov_len_t>(size);
  ddsi_serdata* d = ddsi_serdata_from_ser_iov(t.sertype, SDK_DATA, 1, &iov, size);
  if (d == nullptr) return nullptr;
  void* sample = ddsi_sertype_alloc_sample(t.sertype);
  if (!ddsi_serdata_to_sample(d, sample, nullptr, nullptr))
    keel::fuzz::fail("accepted but not read: ", t.type->ros_name);
  ddsi_serdata_unref(d);
  return sample;
}

}  // namespace

extern "C" int LLVMFuzzerInitialize(int*, char***) {
  keel::fuzz::sampleTypes();  // the participant and sertypes, before the first input
  return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (size < 1) return 0;
  const auto& types = keel::fuzz::sampleTypes();
  const SampleType& t = types[data[0] % types.size()];
  if (overrunsInCyclone(t, data + 1, size - 1)) return -1;
  void* received = receive(t, data + 1, size - 1);
  if (received == nullptr) return 0;
  // What CycloneDDS would write of the sample it received, and what keel writes of it.
  const std::vector<std::uint8_t> by_cyclone = keel::fuzz::serialize(t.sertype, received);
  const std::vector<std::uint8_t> by_keel = t.round_trip(t, received);
  ddsi_sertype_free_sample(t.sertype, received, DDS_FREE_ALL);
  if (by_keel != by_cyclone) keel::fuzz::fail("fromDds then toDds changed the sample of ", t.type->ros_name);
  if (by_keel.empty()) return 0;  // CycloneDDS would not write it: nothing to read again
  void* again = receive(t, by_keel.data(), by_keel.size());
  if (again == nullptr) keel::fuzz::fail("CycloneDDS refuses its own serialization of ", t.type->ros_name);
  const std::vector<std::uint8_t> twice = t.round_trip(t, again);
  ddsi_sertype_free_sample(t.sertype, again, DDS_FREE_ALL);
  if (twice != by_keel) keel::fuzz::fail("a round trip's bytes read again write differently: ", t.type->ros_name);
  return 0;
}
