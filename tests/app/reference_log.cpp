// app/reference_log.cpp: comparing displacement logs, reference headers,
// and reading references as untrusted files.
#include "app/reference_log.hpp"

#include <doctest/doctest.h>
#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <fstream>
#include <sstream>

#include "mesh/generate/box.hpp"
#include "test_support.hpp"

namespace fs = std::filesystem;
using namespace softcut::app;
using softcut::test::contains;
using softcut::test::error_of;

namespace {

const char* kLog = "frame,time,node,ux,uy,uz\n0,0,1,0,0,-1e-3\n1,0.1,1,0,0,-2e-3\n";

ReferenceHeader header_of(const std::string& scenario) {
  ReferenceHeader h;
  h.scenario = scenario;
  h.mesh = "fnv1a64:0123456789abcdef";
  h.params = {{"f", "0.5"}, {"label", "two\nlines \"q\""}};
  h.softcut = "0.0.1";
  return h;
}

}  // namespace

TEST_SUITE("app/reference_log") {
  TEST_CASE("compare_logs: tolerance relative to the motion's scale") {
    const fs::path dir = softcut::test::scratch_dir("check_compare");
    std::ofstream(dir / "a.csv") << kLog;
    std::ofstream(dir / "b.csv") << "frame,time,node,ux,uy,uz\n0,0,1,0,0,-1e-3\n1,0.1,1,0,1e-9,-2e-3\n";
    const auto ok = compare_logs(dir / "a.csv", dir / "b.csv", 1e-6);
    CHECK(ok.ok);
    CHECK(ok.scale == 2e-3);
    CHECK(ok.max_diff == 1e-9);
    CHECK_FALSE(compare_logs(dir / "a.csv", dir / "b.csv", 1e-7).ok);
    std::ofstream(dir / "c.csv") << "frame,time,node,ux,uy,uz\n0,0,1,0,0,-1e-3\n1,0.1,2,0,0,-2e-3\n";
    CHECK(compare_logs(dir / "a.csv", dir / "c.csv", 1).stale);
    std::ofstream(dir / "d.csv") << "frame,time,node,ux,uy,uz\n0,0,1,0,0\n";
    CHECK_THROWS_WITH(compare_logs(dir / "a.csv", dir / "d.csv", 1), doctest::Contains("d.csv:2:"));
    // CRLF line ends, comments and blank lines read as before.
    std::ofstream(dir / "e.csv") << "# made by hand\r\nframe,time,node,ux,uy,uz\r\n\r\n0,0,1,0,0,-1e-3\r\n1,0.1,1,0,0,-2e-3\r\n";
    CHECK(compare_logs(dir / "a.csv", dir / "e.csv", 1e-12).ok);
    // Row counts: a longer log names both counts; a longer reference is not read to its end.
    std::ofstream(dir / "f.csv") << "frame,time,node,ux,uy,uz\n0,0,1,0,0,-1e-3\n";
    const auto shorter = compare_logs(dir / "a.csv", dir / "f.csv", 1);
    CHECK(shorter.stale);
    CHECK(shorter.message == "the log has 2 rows, the reference 1 (frames or logged nodes changed)");
    const auto longer = compare_logs(dir / "f.csv", dir / "a.csv", 1);
    CHECK(longer.message == "the log has 1 rows, the reference more (frames or logged nodes changed)");
  }

  TEST_CASE("reference_path sits next to the scenario") {
    CHECK(reference_path("scenarios/knee.lua") == fs::path("scenarios/knee.ref.csv"));
  }

  TEST_CASE("the header: one line, read back field for field - headerless references still read") {
    const fs::path dir = softcut::test::scratch_dir("ref_header");
    const std::string line = reference_header_line(header_of("kidney_cut"));
    CHECK(line.rfind("# softcut-reference: {\"scenario\":\"kidney_cut\",", 0) == 0);
    CHECK(line.find('\n') == line.size() - 1);  // one line, whatever the values hold
    std::ofstream(dir / "r.ref.csv") << line << kLog;
    const ReferenceHeader h = read_reference_header(LogFile::at(dir / "r.ref.csv"));
    CHECK(h.present);
    CHECK(h.scenario == "kidney_cut");
    CHECK(h.mesh == "fnv1a64:0123456789abcdef");
    CHECK(h.params == header_of("x").params);
    CHECK(h.softcut == "0.0.1");
    std::ofstream(dir / "old.ref.csv") << kLog;
    CHECK_FALSE(read_reference_header(LogFile::at(dir / "old.ref.csv")).present);
    std::ofstream(dir / "log.csv") << kLog;
    CHECK(compare_logs(dir / "log.csv", dir / "old.ref.csv", 1e-12).ok);
    CHECK(compare_logs(dir / "log.csv", dir / "r.ref.csv", 1e-12).ok);
    // A malformed header names the file, the line and the field.
    for (const auto& [text, why] : std::vector<std::pair<std::string, std::string>>{
             {"# softcut-reference: {\"mesh\":\"m\",\"params\":{},\"softcut\":\"1\"}\n", "has no 'scenario' (a string)"},
             {"# softcut-reference: {\"scenario\":\"s\",\"mesh\":\"m\",\"softcut\":\"1\"}\n", "has no 'params' (an object)"},
             {"# softcut-reference: {\"scenario\":\"s\",\"mesh\":\"m\",\"params\":{\"a\":1},\"softcut\":\"1\"}\n",
              "has a parameter 'a' that is not a string"},
             {"# softcut-reference: {\"scenario\":\n", "is not valid JSON"},
             {"# softcut-reference: [1]\n", "is not a JSON object"}}) {
      std::ofstream(dir / "bad.ref.csv", std::ios::trunc) << text << kLog;
      const std::string msg = error_of([&] { read_reference_header(LogFile::at(dir / "bad.ref.csv")); });
      CHECK(contains(msg, "bad.ref.csv:1: the reference header " + why));
    }
  }

  TEST_CASE("who made it: another scenario's reference is foreign - other parameters or mesh are named when it differs") {
    const fs::path dir = softcut::test::scratch_dir("ref_identity");
    std::ofstream(dir / "log.csv") << kLog;
    std::ofstream(dir / "r.ref.csv") << reference_header_line(header_of("vessel_clamp"))
                                     << "frame,time,node,ux,uy,uz\n0,0,1,0,0,-1e-3\n1,0.1,1,0,0,-3e-3\n";
    RunIdentity who{"kidney_cut", "fnv1a64:0123456789abcdef", header_of("x").params};
    const auto foreign = compare_logs(LogFile::at(dir / "log.csv"), LogFile::at(dir / "r.ref.csv"), 1e-6, &who);
    CHECK(foreign.foreign);
    CHECK(!foreign.ok);
    CHECK(foreign.message == "this reference was made by scenario 'vessel_clamp', not 'kidney_cut'");
    who.scenario = "vessel_clamp";
    who.params = {{"f", "0.25"}};
    who.mesh = "fnv1a64:ffffffffffffffff";
    const auto differs = compare_logs(LogFile::at(dir / "log.csv"), LogFile::at(dir / "r.ref.csv"), 1e-6, &who);
    CHECK(!differs.foreign);
    CHECK(!differs.ok);
    CHECK(contains(differs.message, "the reference was recorded with f=0.5 label=two\\x0Alines \"q\", this run has "
                                    "f=0.25; on another mesh (fnv1a64:0123456789abcdef, this run's "
                                    "fnv1a64:ffffffffffffffff)"));
    who.params = header_of("x").params;
    who.mesh = "fnv1a64:0123456789abcdef";
    CHECK(!contains(compare_logs(LogFile::at(dir / "log.csv"), LogFile::at(dir / "r.ref.csv"), 1e-6, &who).message,
                    "recorded with"));  // nothing to add when they agree
  }

  TEST_CASE("copy_as_reference: the header, then the log's bytes unchanged") {
    const fs::path dir = softcut::test::scratch_dir("ref_copy");
    std::ofstream(dir / "log.csv") << kLog;
    std::ostringstream out;
    copy_as_reference(LogFile::at(dir / "log.csv"), header_of("s"), out);
    CHECK(out.str() == reference_header_line(header_of("s")) + kLog);
  }

  TEST_CASE("references are untrusted: no link, no FIFO, bounded lines and bytes, the stop flags polled") {
    const fs::path dir = softcut::test::scratch_dir("ref_hostile");
    std::ofstream(dir / "log.csv") << kLog;
    std::ofstream(dir / "secret.csv") << kLog;
    fs::create_symlink(dir / "secret.csv", dir / "link.ref.csv");
    CHECK(contains(error_of([&] { compare_logs(dir / "log.csv", dir / "link.ref.csv", 1); }),
                   "'link.ref.csv' is a symbolic link"));
    CHECK(contains(error_of([&] { read_reference_header(LogFile::at(dir / "link.ref.csv")); }), "is a symbolic link"));
    REQUIRE(::mkfifo((dir / "fifo.ref.csv").c_str(), 0644) == 0);
    CHECK(contains(error_of([&] { compare_logs(dir / "log.csv", dir / "fifo.ref.csv", 1); }),
                   "'fifo.ref.csv' is not a regular file"));
    {
      const int fd = ::open((dir / "zeros.ref.csv").c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
      REQUIRE(fd >= 0);
      REQUIRE(::ftruncate(fd, off_t(64) << 30) == 0);  // sparse: 64 GB of zeros
      ::close(fd);
    }
    CHECK(contains(error_of([&] { compare_logs(dir / "log.csv", dir / "zeros.ref.csv", 1); }),
                   "zeros.ref.csv:1: a line longer than 65536 bytes"));
    std::ofstream(dir / "blank.ref.csv") << std::string(3 << 20, '\n') << kLog;  // 3 MB of blank lines
    CHECK(contains(error_of([&] { compare_logs(dir / "log.csv", dir / "blank.ref.csv", 1); }),
                   "over twice the log it is compared with"));
    std::atomic<bool> late{true};
    CompareLimits limits;
    limits.timeout = &late;
    limits.timeout_s = 7;
    CHECK(contains(error_of([&] {
                     compare_logs(LogFile::at(dir / "log.csv"), LogFile::at(dir / "secret.csv"), 1, nullptr, limits);
                   }),
                   "the wall-clock limit of 7 s (--timeout) passed while it was read"));
    CompareLimits stop;
    stop.interrupt = &late;
    CHECK(contains(error_of([&] {
                     compare_logs(LogFile::at(dir / "log.csv"), LogFile::at(dir / "secret.csv"), 1, nullptr, stop);
                   }),
                   "interrupted"));
  }

  TEST_CASE("mesh_fingerprint: the same mesh gives the same text, another mesh another") {
    const auto a = softcut::mesh::generate_box({});
    softcut::mesh::BoxOptions o;
    o.nx = 3;
    const auto b = softcut::mesh::generate_box(o);
    CHECK(mesh_fingerprint(a) == mesh_fingerprint(softcut::mesh::generate_box({})));
    CHECK(mesh_fingerprint(a) != mesh_fingerprint(b));
    CHECK(mesh_fingerprint(a).rfind("fnv1a64:", 0) == 0);
    CHECK(mesh_fingerprint(a).size() == 24);
  }
}
