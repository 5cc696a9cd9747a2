#!/usr/bin/env python3
"""cmake/keel_msggen.py as a message author meets it: every bad .msg or .srv is refused with
`file:line: error: what and why` (exit 1, nothing written for it), and good ones give rosidl's
file names, IDL that idlc compiles, C++ headers that include only the standard library and
keel, and each message's table of fields by name. ctest: Msggen.RefusesBadMessagesWithFileAndLine (label unit).

Writes only in a temporary directory; runs idlc when it is installed and cmake -P (for
KeelMessages.cmake's snake case). Standard library only: python3 tests/unit/msgs/msggen_test.py"""
import os
import pathlib
import re
import shutil
import subprocess
import sys
import tempfile

ROOT = pathlib.Path(__file__).resolve().parents[3]
MSGGEN = ROOT / "cmake" / "keel_msggen.py"
SHIPPED = ROOT / "msgs"

# (.msg text, line of the error, words the message must contain)
BAD = {
    "WideName": ("string ok\nwstring name\n", 2, "wstring is not supported"),
    "WideNames": ("# names\nwstring<=8[] names\n", 2, "wstring is not supported"),
    "NoName": ("int32 x\n\nfloat64\n", 3, "a type without a name"),
    "Unknown": ("std_msgs/Header header\nfoo_msgs/Bar bar\n", 2, "unknown message type foo_msgs/Bar"),
    "SamePackage": ("Missing m  # a bare name is this package's\n", 1, "unknown message type test_msgs/Missing"),
    "Typo": ("int33 x\n", 1, "unknown type 'int33'"),
    "ZeroArray": ("int32[0] x\n", 1, "an array size is an integer > 0"),
    "WordArray": ("int32[<=n] x\n", 1, "an array size is an integer > 0"),
    "OpenArray": ("int32] x\n", 1, "ends with ']' but has no '['"),
    "ZeroBound": ("string<=0 s\n", 1, "a string bound is an integer > 0"),
    "TooBig": ("int32 a\nint8 x 300\n", 2, "300 is out of int8's range"),
    "NotBool": ("bool b yes\n", 1, "is not a bool"),
    "NotNumber": ("float64 f 1,5\n", 1, "is not a number"),
    "FloatRange": ("float32 f 1e39\n", 1, "out of float32's range"),
    "LongDefault": ("string<=3 s \"abcd\"\n", 1, "longer than the bound"),
    "FixedDefault": ("int32[3] a [1, 2]\n", 1, "has 2 elements"),
    "BadField": ("int32 Speed\n", 1, "'Speed' is not a field name"),
    "TrailingUnderscore": ("int32 speed_\n", 1, "'speed_' is not a field name"),
    "Twice": ("int32 a\nint32 b\nfloat64 a\n", 3, "field 'a' is defined twice"),
    "ConstantType": ("std_msgs/Header H=1\n", 1, "a constant's type is a primitive type"),
    "WideConstant": ("wstring W=\"x\"\n", 1, "wstring is not supported"),
    "ConstantName": ("int32 lower=1\n", 1, "'lower' is not a constant name"),
    "ConstantValue": ("uint8 U=-1\n", 1, "out of uint8's range"),
    "Ros1Time": ("time stamp\n", 1, "use builtin_interfaces/Time"),
    "MessageDefault": ("std_msgs/Header header 0\n", 1, "cannot have a default value"),
    "BadPackage": ("Foo_Bar/Baz x\n", 1, "is not a package name"),
}


def run(out, *args):
    return subprocess.run([sys.executable, str(MSGGEN), "--out", str(out), *map(str, args)],
                          capture_output=True, text=True, timeout=60)


def write(directory, name, text):
    directory.mkdir(parents=True, exist_ok=True)
    path = directory / name
    path.write_text(text, encoding="utf-8")
    return path


def check(cond, what, failures):
    if not cond:
        failures.append(what)


def check_bad_messages(tmp, failures):
    pkg = tmp / "bad" / "test_msgs" / "msg"
    for name, (text, line, words) in BAD.items():
        path = write(pkg, f"{name}.msg", text)
        out = tmp / "out_bad" / name
        r = run(out, "--search", SHIPPED, path)
        expected = f"{path}:{line}: error: "
        check(r.returncode == 1, f"{name}: exit {r.returncode}, want 1 ({r.stderr.strip()})", failures)
        check(r.stderr.startswith(expected) and words in r.stderr,
              f"{name}: want '{expected}...{words}...', got {r.stderr.strip()!r}", failures)
        check(len(r.stderr.strip().splitlines()) == 1, f"{name}: more than one line: {r.stderr!r}", failures)
        check(not out.exists() or not any(p.is_file() for p in out.rglob("*")),
              f"{name}: files were written for a refused message", failures)


def check_whole_file_errors(tmp, failures):
    loose = write(tmp / "loose", "Speed.msg", "float64 v\n")
    r = run(tmp / "o1", loose)
    check(r.returncode == 1 and f"{loose}: error: the package is not known" in r.stderr,
          f"no package: {r.stderr!r}", failures)
    misplaced = write(tmp / "p" / "my_msgs" / "msg", "Add.srv", "int32 a\n---\nint32 b\n")
    r = run(tmp / "o2", misplaced)
    check(r.returncode == 1 and "the package is not known: put the file in <package>/srv/" in r.stderr,
          f"a .srv in msg/: {r.stderr!r}", failures)
    action = write(tmp / "p" / "my_msgs" / "action", "Go.action", "int32 a\n---\n---\n")
    r = run(tmp / "o2a", action)
    check(r.returncode == 1 and "not a .msg or .srv file (actions are not supported)" in r.stderr,
          f"an action: {r.stderr!r}", failures)
    # A service: one '---' line, errors at the file's own line numbers in either half.
    for name, text, line, words in (
            ("NoSeparator", "int32 a\nint32 b\n", 2, "this file 0"),
            ("TwoSeparators", "int32 a\n---\nint32 b\n---\nint32 c\n", 4, "this file 2"),
            ("BadResponse", "# asks\nint32 a\n---\n# answers\nbool ok\nwstring why\n", 6, "wstring is not supported"),
            ("BadRequest", "int33 a\n---\n", 1, "unknown type 'int33'")):
        path = write(tmp / "p" / "srv_msgs" / "srv", f"{name}.srv", text)
        out = tmp / "o_srv" / name
        r = run(out, "--search", SHIPPED, path)
        check(r.returncode == 1 and r.stderr.startswith(f"{path}:{line}: error: ") and words in r.stderr,
              f"{name}.srv: want '{path}:{line}: error: ...{words}', got {r.stderr.strip()!r}", failures)
        check(not out.exists() or not any(p.is_file() for p in out.rglob("*")),
              f"{name}.srv: files were written for a refused service", failures)
    shipped_srv = write(tmp / "p" / "lifecycle_msgs" / "srv", "GetState.srv", "---\nuint8 id\n")
    r = run(tmp / "o_srv2", "--search", SHIPPED, shipped_srv)
    check(r.returncode == 1 and "lifecycle_msgs/srv/GetState ships with keel" in r.stderr,
          f"redefining a shipped service: {r.stderr!r}", failures)
    lower = write(tmp / "p" / "my_msgs" / "msg", "speed.msg", "float64 v\n")
    r = run(tmp / "o3", lower)
    check(r.returncode == 1 and "'speed' is not a message name" in r.stderr, f"lower-case name: {r.stderr!r}", failures)
    keyword = write(tmp / "p" / "map" / "msg", "Grid.msg", "int32 cells\n")
    r = run(tmp / "o7", keyword)
    check(r.returncode == 1 and f"{keyword}: error: package 'map' cannot be a C++ namespace and IDL module"
          in r.stderr, f"a keyword package: {r.stderr!r}", failures)
    header = write(tmp / "p" / "std_msgs" / "msg", "Header.msg", "string frame_id\n")
    r = run(tmp / "o4", "--search", SHIPPED, header)
    check(r.returncode == 1 and "std_msgs/msg/Header ships with keel" in r.stderr,
          f"redefining a shipped message: {r.stderr!r}", failures)
    a = write(tmp / "p" / "clash_msgs" / "msg", "FooBar.msg", "int32 a\n")
    b = write(tmp / "p" / "clash_msgs" / "msg", "FOOBar.msg", "int32 b\n")
    r = run(tmp / "o5", a, b)
    check(r.returncode == 1 and "would both be keel/msg/clash_msgs/msg/foo_bar.hpp" in r.stderr,
          f"two names, one header: {r.stderr!r}", failures)
    # Several bad files: each is reported, the good one is still generated.
    good = write(tmp / "p" / "mixed_msgs" / "msg", "Good.msg", "int32 a\n")
    bad1 = write(tmp / "p" / "mixed_msgs" / "msg", "Bad1.msg", "wstring w\n")
    bad2 = write(tmp / "p" / "mixed_msgs" / "msg", "Bad2.msg", "\n\nint32\n")
    r = run(tmp / "o6", good, bad1, bad2)
    lines = r.stderr.strip().splitlines()
    check(r.returncode == 1 and len(lines) == 2 and lines[0].startswith(f"{bad1}:1: error:")
          and lines[1].startswith(f"{bad2}:3: error:"), f"several bad files: {r.stderr!r}", failures)
    check((tmp / "o6" / "include" / "keel" / "msg" / "mixed_msgs" / "msg" / "good.hpp").is_file(),
          "several bad files: the good one was not generated", failures)


def rosidl_names():
    """The shipped messages' names and rosidl's header names for them (the ROS 2 headers'
    `geometry_msgs/msg/pose_stamped.hpp`), plus some harder ones."""
    names = {p.stem for p in SHIPPED.glob("*/msg/*.msg")} | {p.stem for p in SHIPPED.glob("*/srv/*.srv")}
    names |= {"MultiDOFJointState", "Pose2D", "ColorRGBA", "HTTPRequest", "A", "ABc", "Vector3Stamped"}
    return sorted(names)


def check_names(tmp, failures):
    sys.path.insert(0, str(MSGGEN.parent))
    import keel_msggen  # noqa: E402 (the module under test)
    want = {"PoseStamped": "pose_stamped", "LaserScan": "laser_scan", "Float64": "float64",
            "MultiDOFJointState": "multi_dof_joint_state", "Pose2D": "pose2_d", "ColorRGBA": "color_rgba",
            "UInt8MultiArray": "u_int8_multi_array", "HTTPRequest": "http_request", "Vector3Stamped": "vector3_stamped"}
    for name, snake in want.items():
        got = keel_msggen.snake_case(name)
        check(got == snake, f"snake case of {name}: {got}, want {snake} (rosidl's)", failures)
    cmake = shutil.which("cmake")
    if not cmake:
        print("-- cmake not found: KeelMessages.cmake's snake case not compared")
        return
    names = rosidl_names()
    script = tmp / "snake.cmake"
    script.write_text(f'include("{ROOT / "cmake" / "KeelMessages.cmake"}")\n'
                      f'foreach(n {" ".join(names)})\n'
                      '  _keel_snake_case(s "${n}")\n  message("${n} ${s}")\nendforeach()\n')
    r = subprocess.run([cmake, "-P", str(script)], capture_output=True, text=True, timeout=60)
    got = dict(line.split() for line in r.stderr.splitlines() if line.strip())
    for name in names:
        check(got.get(name) == keel_msggen.snake_case(name),
              f"KeelMessages.cmake names {name} {got.get(name)}, keel_msggen.py {keel_msggen.snake_case(name)}",
              failures)


def check_shipped(tmp, failures):
    out = tmp / "shipped"
    files = sorted(SHIPPED.glob("*/msg/*.msg")) + sorted(SHIPPED.glob("*/srv/*.srv"))
    r = run(out, *files)
    check(r.returncode == 0, f"keel's shipped messages: exit {r.returncode}: {r.stderr}", failures)
    allowed = re.compile(r'#include (<[a-z_]+>|"keel/[a-z0-9_/]+\.hpp")$')
    for header in (out / "include").rglob("*.hpp"):
        if "detail" in header.parts:
            continue
        for line in header.read_text().splitlines():
            if line.startswith("#include"):
                check(allowed.match(line) is not None, f"{header.name} includes {line}", failures)
    pose = (out / "include" / "keel" / "msg" / "geometry_msgs" / "msg" / "pose_stamped.hpp").read_text()
    check("struct PoseStamped {" in pose and "::keel::msg::std_msgs::Header header{};" in pose
          and 'KEEL_TYPE_NAME(keel::msg::geometry_msgs::PoseStamped, "geometry_msgs/msg/PoseStamped");' in pose,
          "pose_stamped.hpp lacks the struct, its header field or its type name", failures)
    empty_fields = (out / "include" / "keel" / "msg" / "std_msgs" / "msg" / "detail" / "empty__fields.hpp").read_text()
    check("static std::span<const MessageField> fields() { return {}; }" in empty_fields
          and "kFields" not in empty_fields, "empty__fields.hpp: a message without fields has an empty table", failures)
    empty = (out / "idl" / "std_msgs" / "msg" / "Empty_.idl").read_text()
    check("uint8 structure_needs_at_least_one_member;" in empty, "Empty_.idl has no placeholder member", failures)
    status = (out / "idl" / "diagnostic_msgs" / "msg" / "DiagnosticStatus_.idl").read_text()
    check("module diagnostic_msgs { module msg { module dds_ {" in status and "@final struct DiagnosticStatus_ {" in status
          and "octet level;" in status and "sequence<::diagnostic_msgs::msg::dds_::KeyValue_ > values;" in status
          and "OK" not in status, "DiagnosticStatus_.idl is not rosidl's DDS form (or has constants)", failures)
    # A service is two messages, as rmw puts it on DDS: pkg::srv::dds_::Name_Request_ and _Response_.
    request = (out / "idl" / "lifecycle_msgs" / "srv" / "ChangeState_Request_.idl").read_text()
    check("module lifecycle_msgs { module srv { module dds_ {" in request
          and "@final struct ChangeState_Request_ {" in request
          and "::lifecycle_msgs::msg::dds_::Transition_ transition;" in request
          and '#include "lifecycle_msgs/msg/Transition_.idl"' in request,
          "ChangeState_Request_.idl is not rmw's DDS form of the service's request", failures)
    get_request = (out / "idl" / "lifecycle_msgs" / "srv" / "GetState_Request_.idl").read_text()
    check("uint8 structure_needs_at_least_one_member;" in get_request, "GetState_Request_.idl: an empty request",
          failures)
    srv = out / "include" / "keel" / "msg" / "lifecycle_msgs" / "srv"
    response = (srv / "change_state_response.hpp").read_text()
    check("struct ChangeState_Response {" in response and "bool success{};" in response
          and 'KEEL_TYPE_NAME(keel::msg::lifecycle_msgs::ChangeState_Response, '
              '"lifecycle_msgs/srv/ChangeState_Response");' in response,
          "change_state_response.hpp lacks the struct, its field or its type name", failures)
    service = (srv / "change_state.hpp").read_text()
    check('#include "keel/msg/lifecycle_msgs/srv/change_state_request.hpp"' in service
          and "using Request = ChangeState_Request;" in service and "using Response = ChangeState_Response;" in service,
          "change_state.hpp does not name the service's two halves", failures)
    source = (out / "src" / "lifecycle_msgs" / "srv" / "change_state_request__dds.cpp").read_text()
    check('#include "lifecycle_msgs/srv/ChangeState_Request_.c"' in source
          and "::lifecycle_msgs_srv_dds__ChangeState_Request_" in source,
          "change_state_request__dds.cpp: idlc's C file or C type of a service's request", failures)
    imu = (out / "idl" / "sensor_msgs" / "msg" / "Imu_.idl").read_text()
    check("double orientation_covariance[9];" in imu and '#include "std_msgs/msg/Header_.idl"' in imu,
          "Imu_.idl: fixed array or include", failures)

    # A second run changes no file (a build then recompiles nothing).
    stamps = {p: p.stat().st_mtime_ns for p in out.rglob("*") if p.is_file()}
    run(out, *files)
    touched = [p.name for p, t in stamps.items() if p.stat().st_mtime_ns != t]
    check(not touched, f"a second run rewrote {touched[:5]}", failures)
    return out


def check_user_messages(tmp, shipped_out, failures):
    pkg = tmp / "user" / "robot_msgs" / "msg"
    write(pkg, "Wheel.msg", "string name\nfloat64 speed\n")
    drive = write(pkg, "Drive.msg", "Header header  # std_msgs/Header\ngeometry_msgs/Twist cmd\nWheel[4] wheels\n"
                                    "int32 class\nuint8 module\n")
    set_speed = write(tmp / "user" / "robot_msgs" / "srv", "SetSpeed.srv",
                      "# Sets a wheel's speed\nWheel wheel\n---\nbool accepted\nstd_msgs/Header header\n")
    out = tmp / "user_out"
    r = run(out, "--search", SHIPPED, pkg / "Wheel.msg", drive, set_speed)
    check(r.returncode == 0, f"a user's messages: {r.stderr}", failures)
    request = (out / "include" / "keel" / "msg" / "robot_msgs" / "srv" / "set_speed_request.hpp").read_text()
    check("::keel::msg::robot_msgs::Wheel wheel{};" in request and "/// Sets a wheel's speed" in request
          and '#include "keel/msg/robot_msgs/msg/wheel.hpp"' in request,
          "set_speed_request.hpp: a field of the package's own message, or its comment", failures)
    answer = (out / "idl" / "robot_msgs" / "srv" / "SetSpeed_Response_.idl").read_text()
    check("::std_msgs::msg::dds_::Header_ header;" in answer, "SetSpeed_Response_.idl: a shipped type", failures)
    hpp = (out / "include" / "keel" / "msg" / "robot_msgs" / "msg" / "drive.hpp").read_text()
    check('#include "keel/msg/std_msgs/msg/header.hpp"' in hpp and "std::int32_t class_{};" in hpp
          and "std::uint8_t module{};" in hpp and "std::array<::keel::msg::robot_msgs::Wheel, 4> wheels{};" in hpp,
          "drive.hpp: Header, a keyword field or a same-package array", failures)
    fields = (out / "include" / "keel" / "msg" / "robot_msgs" / "msg" / "detail" / "drive__fields.hpp").read_text()
    check('#include "keel/msg/robot_msgs/msg/detail/wheel__fields.hpp"' in fields
          and "struct MessageFieldsOf<::keel::msg::robot_msgs::Drive> {" in fields
          and '{"wheels", "robot_msgs/msg/Wheel[4]", FieldKind::Message, true, '
              '&MessageFieldsOf<::keel::msg::robot_msgs::Wheel>::fields,' in fields
          and '{"class", "int32", FieldKind::Number, false, nullptr,' in fields
          and "&visitNumbers<&M::class_>, nullptr}," in fields
          and '{"cmd", "geometry_msgs/msg/Twist", FieldKind::Message, false,' in fields,
          "drive__fields.hpp: a table entry for an array of messages, a keyword field or a shipped type", failures)
    wheel = (out / "include" / "keel" / "msg" / "robot_msgs" / "msg" / "detail" / "wheel__fields.hpp").read_text()
    check('{"name", "string", FieldKind::String, false, nullptr,\n       nullptr, nullptr},' in wheel
          and '{"speed", "float64", FieldKind::Number, false, nullptr,' in wheel,
          "wheel__fields.hpp: a string is no number, a float64 is", failures)
    source = (out / "src" / "robot_msgs" / "msg" / "drive__dds.cpp").read_text()
    check('#include "keel/msg/robot_msgs/msg/detail/drive__fields.hpp"' in source,
          "drive__dds.cpp does not include its fields' table, which its registration carries", failures)
    idl = (out / "idl" / "robot_msgs" / "msg" / "Drive_.idl").read_text()
    check("int32 class_;" in idl and "uint8 module_;" in idl and "::robot_msgs::msg::dds_::Wheel_ wheels[4];" in idl,
          "Drive_.idl: keyword fields or the array of a same-package type", failures)
    idlc = shutil.which("idlc")
    if not idlc:
        print("-- idlc not found: the IDL is not compiled")
        return
    for root, base in ((shipped_out, []), (out, ["-I", str(shipped_out / "idl")])):
        for idl_file in sorted((root / "idl").rglob("*.idl")):
            rel = idl_file.relative_to(root)
            r = subprocess.run([idlc, "-t", "-x", "final", "-I", "idl", *base, "-b", "idl", "-o", "idlc", str(rel)],
                               cwd=root, capture_output=True, text=True, timeout=60)
            check(r.returncode == 0, f"idlc {rel}: {r.stdout}{r.stderr}", failures)


def main():
    failures = []
    with tempfile.TemporaryDirectory() as t:
        tmp = pathlib.Path(t)
        check_bad_messages(tmp, failures)
        check_whole_file_errors(tmp, failures)
        check_names(tmp, failures)
        shipped_out = check_shipped(tmp, failures)
        check_user_messages(tmp, shipped_out, failures)
    for f in failures:
        print("FAIL:", f if len(f) < 600 else f[:600] + " ...")
    print("msggen_test:", "passed" if not failures else f"{len(failures)} failure(s)")
    return 1 if failures else 0


if __name__ == "__main__":
    os.environ.pop("PYTHONPATH", None)
    sys.exit(main())
