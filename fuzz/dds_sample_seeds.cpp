// Not a fuzz target: writes dds_sample's seeds (fuzz/corpus/dds_sample/), each a value of one of the
// target's types (fuzz/dds_sample.hpp) converted by keel's toDds and serialized by CycloneDDS
// (dds_stream_write_sampleLE/BE, the code its writers run) behind the byte that selects its type
// and the CDR header a writer puts before it: in each of the four encodings a reader accepts for
// keel's final types (CDR1 and CDR2, little- and big-endian). Checks on the way that CycloneDDS's
// own serialization of the sample is the little-endian CDR1 seed, byte for byte. Built only when
// asked for (--target fuzz_dds_sample_seeds).
//   build-fuzz/fuzz/dds_sample_seeds fuzz/corpus/dds_sample
#include <dds/ddsi/ddsi_cdrstream.h>

#include <cstdint>
#include <cstdio>
#include <fstream>
#include <string>
#include <vector>

#include "dds_sample.hpp"
#include "unit/msgs/sample_values.hpp"

namespace {

namespace msg = keel::msg;
using Bytes = std::vector<std::uint8_t>;

struct Encoding {
  const char* name;
  std::uint8_t identifier;     // the CDR header's second byte (the first is 0)
  std::uint32_t xcdr_version;  // CycloneDDS's CDR_ENC_VERSION_1 or _2
  bool big_endian;
};
constexpr Encoding kEncodings[] = {
    {"cdr1_le", 0x01, 1, false},
    {"cdr1_be", 0x00, 1, true},
    {"cdr2_le", 0x07, 2, false},
    {"cdr2_be", 0x06, 2, true},
};

/// The C sample `c` serialized as a writer in `e` sends it: header, body, padding to 4 bytes
/// (counted in the header's options, as CycloneDDS's writers do).
Bytes encode(const ddsi_sertype* sertype, const void* c, const Encoding& e) {
  const auto* type = reinterpret_cast<const ddsi_sertype_default*>(sertype);
  dds_ostream_t os;
  bool ok = false;
  if (e.big_endian) {
    dds_ostreamBE_t be;
    dds_ostreamBE_init(&be, 0, e.xcdr_version);
    ok = dds_stream_write_sampleBE(&be, c, type);
    os = be.x;
  } else {
    dds_ostreamLE_t le;
    dds_ostreamLE_init(&le, 0, e.xcdr_version);
    ok = dds_stream_write_sampleLE(&le, c, type);
    os = le.x;
  }
  if (!ok) keel::fuzz::fail("CycloneDDS cannot write a seed in ", e.name);
  const auto pad = static_cast<std::uint8_t>((4 - os.m_index % 4) % 4);
  Bytes bytes{0x00, e.identifier, 0x00, pad};
  bytes.insert(bytes.end(), os.m_buffer, os.m_buffer + os.m_index);
  bytes.insert(bytes.end(), pad, 0);
  dds_ostream_fini(&os);
  return bytes;
}

/// Writes seeds into `dir`, each value in the four encodings.
struct SeedWriter {
  std::string dir;
  int written = 0;

  template <class C, class T>
  void seed(std::size_t index, const std::string& name, const T& value) {
    const keel::fuzz::SampleType& t = keel::fuzz::sampleTypes().at(index);
    C c{};
    keel::detail::DdsScratch scratch;
    keel::msg::dds::toDds(value, c, scratch);
    for (const Encoding& e : kEncodings) {
      const Bytes bytes = encode(t.sertype, &c, e);
      if (e.identifier == 0x01 && bytes != keel::fuzz::serialize(t.sertype, &c)) {
        keel::fuzz::fail("the little-endian CDR1 seed is not CycloneDDS's serialization: ", name.c_str());
      }
      std::ofstream out(dir + "/" + name + "_" + e.name, std::ios::binary);
      out.put(static_cast<char>(index));
      out.write(reinterpret_cast<const char*>(bytes.data()), static_cast<std::streamsize>(bytes.size()));
      if (!out) keel::fuzz::fail("cannot write in ", dir.c_str());
      ++written;
    }
  }
};

msg::std_msgs::String text(std::string s) {
  msg::std_msgs::String m;
  m.data = std::move(s);
  return m;
}

msg::std_msgs::Float64MultiArray multiArray() {
  msg::std_msgs::Float64MultiArray a;
  a.layout.dim = {{"rows", 2, 6}, {"cols", 3, 3}};
  a.layout.data_offset = 1;
  a.data = {0.0, 1.0, 2.0, 3.0, 4.0, 5.0, 6.0};
  return a;
}

}  // namespace

int main(int argc, char** argv) {
  if (argc != 2) {
    std::fprintf(stderr, "usage: dds_sample_seeds DIR\n");
    return 2;
  }
  SeedWriter w{argv[1]};
  w.seed<sensor_msgs_msg_dds__LaserScan_>(0, "laser_scan_empty", msg::sensor_msgs::LaserScan{});
  w.seed<sensor_msgs_msg_dds__LaserScan_>(0, "laser_scan_5", keel::test::laserScan(5));
  w.seed<std_msgs_msg_dds__String_>(1, "string_empty", text(""));
  w.seed<std_msgs_msg_dds__String_>(1, "string_utf8", text("hello, ROS 2 — ünïcödé 🤖"));
  w.seed<std_msgs_msg_dds__String_>(1, "string_not_utf8", text("\xff\xfe\xc3(\xed\xa0\x80 bytes"));
  w.seed<diagnostic_msgs_msg_dds__DiagnosticArray_>(2, "diagnostic_array_empty",
                                                    msg::diagnostic_msgs::DiagnosticArray{});
  w.seed<diagnostic_msgs_msg_dds__DiagnosticArray_>(2, "diagnostic_array", keel::test::diagnosticArray());
  w.seed<geometry_msgs_msg_dds__Twist_>(3, "twist", keel::test::twist());
  w.seed<keel_test_msgs_msg_dds__Everything_>(4, "everything_default", msg::keel_test_msgs::Everything{});
  w.seed<keel_test_msgs_msg_dds__Everything_>(4, "everything", keel::test::everything());
  w.seed<sensor_msgs_msg_dds__JointState_>(5, "joint_state", keel::test::jointState());
  w.seed<sensor_msgs_msg_dds__Imu_>(6, "imu", keel::test::imu());
  w.seed<std_msgs_msg_dds__Float64MultiArray_>(7, "float64_multi_array", multiArray());
  std::printf("dds_sample_seeds: %d seeds in %s\n", w.written, w.dir.c_str());
  return 0;
}
