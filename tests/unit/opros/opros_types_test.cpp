// keel's OPRoS-compatible basic types, events, archives and device types
// (include/keel/opros/{ReturnType,OPRoSTypes,Event,EventData}.h, archive/, device/): what OPRoS
// code does with them compiles and behaves, and what a malformed stream does is an exception.
#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <complex>
#include <cstdint>
#include <deque>
#include <limits>
#include <list>
#include <map>
#include <queue>
#include <set>
#include <sstream>
#include <stack>
#include <string>
#include <type_traits>
#include <unordered_map>
#include <valarray>
#include <vector>

#include "include/keel/opros/ArchiveFactory.h"
#include "include/keel/opros/ArgumentNumberException.h"
#include "include/keel/opros/EventData.h"
#include "include/keel/opros/MethodInvokeException.h"
#include "include/keel/opros/OPRoSTypes.h"
#include "include/keel/opros/archive/opros_access.h"
#include "include/keel/opros/archive/opros_archive.h"
#include "include/keel/opros/device/ApiTypes.h"
#include "include/keel/opros/device/ApiTypes.h"  // NOLINT(readability-duplicate-include): twice, as HelloMaker.cpp does
#include "include/keel/opros/device/OprosPrintMessage.h"
#include "include/keel/opros/device/Property.h"

// A user data type as the OPRoS code generator writes one (OneComp's PersonData), but with its
// save/load private, so that only the friendship with opros::archive::access reaches them.
class PersonData {
 public:
  PersonData() = default;
  PersonData(int age, std::string name) : m_age(age), m_name(std::move(name)) {}
  int& getAge() { return m_age; }
  std::string& getName() { return m_name; }

 private:
  friend class opros::archive::access;
  void save(opros::archive::oarchive& ar, const unsigned int) {
    ar << m_age;
    ar << m_name;
  }
  void load(opros::archive::iarchive& ar, const unsigned int) {
    ar >> m_age;
    ar >> m_name;
  }
  int m_age = 0;
  std::string m_name;
};
inline std::string typeName(PersonData*) { return "PersonData"; }

// Serialised from outside, OPRoS's other way.
struct Waypoint {
  double x = 0;
  double y = 0;
};
inline void save_this(opros::archive::oarchive& ar, Waypoint& w) { ar << w.x << w.y; }
inline void load_this(opros::archive::iarchive& ar, Waypoint& w) { ar >> w.x >> w.y; }

// Serialised with one template member and `&`, boost's way.
struct Gains {
  double kp = 0;
  double ki = 0;
  template <class Archive>
  void serialize(Archive& ar, const unsigned int) {
    ar& kp& ki;
  }
};

enum Mode { kIdle, kRunning = 7 };
struct Unnamed {};

// 2012 code names these unqualified (the device headers make them so).
vector<valarray<double>> kitech_path(2, valarray<double>(3));
Property kitech_parameter;
map<string, string> kitech_map;

namespace {

ReturnType returnsBadInput() { return OPROS_BAD_INPUT_PARAMETER; }

template <typename T>
T roundTripBinary(const T& value) {
  std::stringstream stream;
  opros::archive::binary_oarchive out(&stream);
  out << value;
  opros::archive::binary_iarchive in(&stream);
  T loaded{};
  in >> loaded;
  EXPECT_EQ(stream.peek(), std::char_traits<char>::eof()) << "the reader left bytes unread";
  return loaded;
}

template <typename Out, typename In, typename T>
T roundTrip(const T& value, int mode = 0) {
  std::stringstream stream;
  if constexpr (std::is_same_v<Out, opros::archive::string_oarchive>) {
    Out out(&stream, mode);
    out << value;
  } else {
    Out out(&stream);
    out << value;
  }
  In in(&stream);
  T loaded{};
  in >> loaded;
  return loaded;
}

std::string savedBinary(const auto& value) {
  std::stringstream stream;
  opros::archive::binary_oarchive out(stream);
  out << value;
  return stream.str();
}

// ---- ReturnType ----

TEST(OprosTypesReturnType, CodesHaveOprosValues) {
  EXPECT_EQ(OPROS_SUCCESS, 200);
  EXPECT_EQ(OPROS_SUCCESS_SYNC, 202);
  EXPECT_EQ(OPROS_BAD_INPUT_PARAMETER, 401);
  EXPECT_EQ(OPROS_PRECONDITION_NOT_MET, 405);
  EXPECT_EQ(OPROS_OUT_OF_RESOURCES, 408);
  EXPECT_EQ(OPROS_UNSUPPORTED_METHOD, 501);
  EXPECT_EQ(OPROS_VERSION_MISMATCH, 505);
  EXPECT_EQ(OPROS_DESTORY_ERROR, 0x10000000);
  EXPECT_EQ(OPROS_SET_PROPERTY_ERROR, 0x10000004);
  EXPECT_EQ(OPROS_RECOVER_API_ERROR, 0x10000103);
  EXPECT_EQ(OPROS_CALL_API_ERROR, 0x20000102);
  // The two the 2015 header misprinted with nine hex digits.
  EXPECT_EQ(OPROS_API_NOT_SUPPORTED_ERROR, 0x20000103);
  EXPECT_EQ(OPROS_API_EXECUTING, 0x20000104);
  EXPECT_EQ(OPROS_ERROR, 302);
  EXPECT_EQ(UNKNOWN_ERROR, 210u);
  static_assert(std::is_same_v<ReturnType, unsigned int>);
}

TEST(OprosTypesReturnType, CodesAreStoredComparedReturnedAndSwitchedOn) {
  ReturnType stored = OPROS_SUCCESS;
  EXPECT_TRUE(stored == OPROS_SUCCESS);
  stored = returnsBadInput();
  EXPECT_NE(stored, OPROS_SUCCESS);
  int branch = 0;
  switch (stored) {
    case OPROS_SUCCESS: branch = 1; break;
    case OPROS_BAD_INPUT_PARAMETER: branch = 2; break;
    default: branch = 3; break;
  }
  EXPECT_EQ(branch, 2);
}

// ---- opros_any ----

TEST(OprosTypesAny, IsEmptyByDefault) {
  opros_any any;
  EXPECT_TRUE(any.empty());
  EXPECT_EQ(any.type(), typeid(void));
  EXPECT_EQ(any.getTypeName(), "void");
  EXPECT_EQ(opros_any_cast<int>(&any), nullptr);
}

TEST(OprosTypesAny, HoldsACopyAndRemembersItsOprosTypeName) {
  std::string text = "hello";
  opros_any any = text;
  text = "changed";
  EXPECT_FALSE(any.empty());
  EXPECT_EQ(any.type(), typeid(std::string));
  EXPECT_EQ(any.getTypeName(), "std::string");
  ASSERT_NE(opros_any_cast<std::string>(&any), nullptr);
  EXPECT_EQ(*opros_any_cast<std::string>(&any), "hello");

  opros_any person = PersonData(30, "kim");
  EXPECT_EQ(person.getTypeName(), "PersonData");
  EXPECT_EQ(opros_any_cast<PersonData>(person).getName(), "kim");
}

TEST(OprosTypesAny, CopiesAreIndependentAndMovesTransfer) {
  opros_any original = std::vector<int>{1, 2, 3};
  opros_any copy = original;
  opros_any_cast<std::vector<int>>(&copy)->push_back(4);
  EXPECT_EQ(opros_any_cast<std::vector<int>>(&original)->size(), 3u);
  EXPECT_EQ(opros_any_cast<std::vector<int>>(&copy)->size(), 4u);

  opros_any assigned;
  assigned = copy;
  opros_any_cast<std::vector<int>>(&assigned)->clear();
  EXPECT_EQ(opros_any_cast<std::vector<int>>(&copy)->size(), 4u);

  opros_any moved = std::move(copy);
  EXPECT_EQ(opros_any_cast<std::vector<int>>(&moved)->size(), 4u);

  moved = 2.5;  // assigning a value replaces what it held
  EXPECT_EQ(moved.type(), typeid(double));
  EXPECT_EQ(opros_any_cast<std::vector<int>>(&moved), nullptr);
}

TEST(OprosTypesAny, RejectsAWrongType) {
  opros_any any = 1.5;
  const opros_any& constant = any;
  EXPECT_EQ(opros_any_cast<int>(&any), nullptr);
  EXPECT_EQ(opros_any_cast<float>(&constant), nullptr);
  EXPECT_EQ(unsafe_opros_any_cast<int>(&any), nullptr);
  EXPECT_EQ(opros_any_cast<int>(static_cast<opros_any*>(nullptr)), nullptr);
  ASSERT_NE(opros_any_cast<double>(&constant), nullptr);
  EXPECT_EQ(*opros_any_cast<double>(&constant), 1.5);

  try {
    (void)opros_any_cast<int>(any);
    FAIL() << "a wrong type did not throw";
  } catch (const bad_opros_any_cast& e) {
    EXPECT_STREQ(e.what(), "opros_any_cast: the value holds double, not int");
  }
  EXPECT_THROW((void)opros_any_cast<std::string>(constant), std::bad_cast);
}

TEST(OprosTypesAny, ReferenceCastReachesTheHeldValue) {
  opros_any any = 1;
  opros_any_cast<int&>(any) = 5;
  EXPECT_EQ(opros_any_cast<int>(any), 5);
}

TEST(OprosTypesAny, CastingMacrosWorkAsInGeneratedCode) {
  opros_any any = std::string("msg");
  std::string* text = ANY_CASTING(std::string, &any);
  ASSERT_NE(text, nullptr);
  EXPECT_EQ(*text, "msg");
  EXPECT_EQ(UNSAFE_ANY_CASTING(int, &any), nullptr);
  EventData<int> event;
  Event* base = &event;
  EXPECT_EQ(SAFE_CASTING(EventData<int>*, base), &event);
}

TEST(OprosTypesAny, ParamsEncodeAndDecodeThroughAnArchive) {
  opros_params sent = std::vector<std::string>{"a", "b"};
  EXPECT_EQ(sent.getTypeName(), "std::vector<std::string>");
  std::stringstream stream;
  opros::archive::binary_oarchive out(&stream);
  sent.encode(out);

  opros_params received;
  received.setType(static_cast<std::vector<std::string>*>(nullptr));
  opros::archive::binary_iarchive in(&stream);
  received.decode(in);
  ASSERT_NE(opros_params_cast<std::vector<std::string>>(&received), nullptr);
  EXPECT_EQ(opros_params_cast<std::vector<std::string>>(received), (std::vector<std::string>{"a", "b"}));
  EXPECT_EQ(opros_params_cast<int>(&received), nullptr);
}

TEST(OprosTypesAssert, ThrowsAStdExceptionNamingTheCondition) {
  void* method = nullptr;
  EXPECT_NO_THROW(opros_assert(method == nullptr));
  try {
    opros_assert(method != NULL);  // NOLINT(modernize-use-nullptr): the macro as OPRoS code calls it
    FAIL() << "opros_assert did not throw";
  } catch (const std::exception& e) {
    EXPECT_NE(std::string(e.what()).find("method != NULL"), std::string::npos) << e.what();
    EXPECT_NE(dynamic_cast<const AssertException*>(&e), nullptr);
  }
}

TEST(OprosTypesEnums, HaveOprosEnumeratorsAndQueueLimit) {
  DataPortPolicy policy = OPROS_LAST;
  EXPECT_EQ(policy, 3);
  EXPECT_EQ(OPROS_CS_DESTROYED, 5);
  EXPECT_EQ(OPROS_REMOTE_DATA, 3);
  EXPECT_EQ(OPROS_MT_REMOTE, 2);
  EXPECT_EQ(OPROS_SERVICE_PORT_PROVIDED, 1);
  EXPECT_EQ(DEFAULT_QUEUE_LIMIT, 15);
}

TEST(OprosTypesExceptions, CarryTheirMessages) {
  MethodInvokeException invoke("GetSensorValue is not connected");
  EXPECT_EQ(invoke.getMessage(), "GetSensorValue is not connected");
  EXPECT_STREQ(invoke.what(), "GetSensorValue is not connected");
  ArgumentNumberException arity(42, 2);
  EXPECT_EQ(arity.getMessage(), "line 42: the method requires 2 arguments");
  const std::exception& base = arity;
  EXPECT_STREQ(base.what(), "line 42: the method requires 2 arguments");
}

// ---- typeName ----

TEST(OprosTypesTypeName, SpellsPrimitivesAsOprosDoes) {
  EXPECT_EQ(getTypeName(static_cast<int*>(nullptr)), "int");
  EXPECT_EQ(getTypeName(static_cast<unsigned long long*>(nullptr)), "unsigned long long");
  EXPECT_EQ(getTypeName(static_cast<unsigned char*>(nullptr)), "unsigned char");
  EXPECT_EQ(getTypeName(static_cast<long double*>(nullptr)), "long double");
  EXPECT_EQ(getTypeName(static_cast<wchar_t*>(nullptr)), "w_char_t");
  EXPECT_EQ(getTypeName(static_cast<std::string*>(nullptr)), "std::string");
  EXPECT_EQ(getTypeName(static_cast<const double*>(nullptr)), "double");
}

TEST(OprosTypesTypeName, ComposesContainersAndUserTypes) {
  EXPECT_EQ(getTypeName(static_cast<std::vector<int>*>(nullptr)), "std::vector<int>");
  EXPECT_EQ(getTypeName(static_cast<std::map<std::string, double>*>(nullptr)), "std::map<std::string,double>");
  EXPECT_EQ(getTypeName(static_cast<std::vector<std::list<float>>*>(nullptr)), "std::vector<std::list<float>>");
  EXPECT_EQ(getTypeName(static_cast<std::valarray<double>*>(nullptr)), "std::valarray<double>");
  EXPECT_EQ(getTypeName(static_cast<std::vector<PersonData>*>(nullptr)), "std::vector<PersonData>");
  EXPECT_EQ(getTypeName(static_cast<int**>(nullptr)), "int*");
  EXPECT_EQ(getTypeName(static_cast<EventData<std::string>*>(nullptr)), "EventData<std::string>");
  EXPECT_EQ(getTypeName(static_cast<std::vector<OPRoS::Float64Array>*>(nullptr)), "std::vector<Float64Array>");
}

TEST(OprosTypesTypeName, NamesAnEnumEnumAndAnUnnamedTypeByItsCxxName) {
  EXPECT_EQ(getTypeName(static_cast<Mode*>(nullptr)), "Enum");
  EXPECT_EQ(getTypeName(static_cast<Unnamed*>(nullptr)), "Unnamed");
}

// ---- Event, EventData ----

TEST(OprosEvent, StartsWithIdEventAndKeepsWhatIsSet) {
  EventData<std::string> event;
  EXPECT_EQ(event.getId(), "event");
  EXPECT_EQ(event.getContentData(), nullptr);
  event.setId("messageid");
  event.setTopic("chat");
  event.setComponentId("HelloMaker");
  event.setPortId("EventOut");
  EXPECT_EQ(event.setContentData("hello world"), static_cast<ReturnType>(OPROS_SUCCESS));

  Event* evt = &event;  // as onEvent receives it
  EXPECT_EQ(evt->getId().compare("messageid"), 0);
  EventData<std::string>* typed = (EventData<std::string>*)(evt);  // NOLINT(modernize-use-auto): as OPRoS code casts
  ASSERT_NE(typed->getContentData(), nullptr);
  EXPECT_EQ(*typed->getContentData(), "hello world");
  EXPECT_EQ(evt->getTopic(), "chat");
  EXPECT_EQ(evt->getComponentId(), "HelloMaker");
  EXPECT_EQ(evt->getPortId(), "EventOut");
  EXPECT_EQ(evt->getContent().getTypeName(), "std::string");
}

TEST(OprosEvent, RejectsContentOfAnotherType) {
  EventData<int> event;
  event.setContentData(4);
  opros_any wrong = std::string("four");
  EXPECT_EQ(event.setContent(wrong), static_cast<ReturnType>(OPROS_BAD_INPUT_PARAMETER));
  ASSERT_NE(event.getContentData(), nullptr);
  EXPECT_EQ(*event.getContentData(), 4);
  opros_any right = 5;
  EXPECT_EQ(event.setContent(right), static_cast<ReturnType>(OPROS_SUCCESS));
  EXPECT_EQ(*event.getContentData(), 5);
}

TEST(OprosEvent, CopiesOwnTheirIdsAndContent) {
  EventData<std::vector<int>> original;
  original.setId("a");
  original.setContentData({1, 2});

  EventData<std::vector<int>> copy(original);
  copy.setId("b");
  copy.getContentData()->push_back(3);
  EXPECT_EQ(original.getId(), "a");
  EXPECT_EQ(original.getContentData()->size(), 2u);

  EventData<std::vector<int>> assigned;
  assigned = original;
  original.setContentData({9});
  EXPECT_EQ(assigned.getId(), "a");
  EXPECT_EQ(*assigned.getContentData(), (std::vector<int>{1, 2}));

  std::vector<EventData<std::vector<int>>> queue;  // as keel queues them
  queue.push_back(assigned);
  queue.push_back(std::move(copy));
  EXPECT_EQ(queue[1].getId(), "b");
  EXPECT_EQ(queue[1].getContentData()->size(), 3u);
}

TEST(OprosEvent, CloneIsADeepCopyOfTheSameKind) {
  EventData<std::string> event;
  event.setId("android");
  event.setContentData("x");
  Event* clone = event.clone();
  auto* typed = dynamic_cast<EventData<std::string>*>(clone);
  ASSERT_NE(typed, nullptr);
  EXPECT_EQ(typed->getId(), "android");
  *typed->getContentData() = "y";
  EXPECT_EQ(*event.getContentData(), "x");
  delete clone;
}

TEST(OprosEvent, GettersWorkOnConstEvents) {
  EventData<int> event;
  event.setId("c");
  event.setContentData(3);
  const EventData<int>& constant = event;
  EXPECT_EQ(constant.getId(), "c");
  EXPECT_EQ(constant.getTopic(), "");
  ASSERT_NE(constant.getContentData(), nullptr);
  EXPECT_EQ(*constant.getContentData(), 3);
  EXPECT_FALSE(constant.getContent().empty());
  std::ostringstream printed;
  printed << constant;
  EXPECT_EQ(printed.str(), "[eventid:c,topic:,componentid:,portid:]");
}

TEST(OprosEvent, RoundTripsThroughAnArchive) {
  EventData<PersonData> event;
  event.setId("person");
  event.setPortId("out");
  event.setContentData(PersonData(7, "lee"));
  EventData<PersonData> loaded = roundTripBinary(event);
  EXPECT_EQ(loaded.getId(), "person");
  EXPECT_EQ(loaded.getPortId(), "out");
  ASSERT_NE(loaded.getContentData(), nullptr);
  EXPECT_EQ(loaded.getContentData()->getName(), "lee");

  EventData<int> empty;
  EXPECT_EQ(roundTripBinary(empty).getContentData(), nullptr);
}

// ---- archives ----

TEST(OprosArchive, RoundTripsEveryPrimitive) {
  EXPECT_EQ(roundTripBinary(true), true);
  EXPECT_EQ(roundTripBinary('z'), 'z');
  EXPECT_EQ(roundTripBinary(static_cast<signed char>(-5)), -5);
  EXPECT_EQ(roundTripBinary(static_cast<unsigned char>(250)), 250);
  EXPECT_EQ(roundTripBinary(L'\x263A'), L'\x263A');
  EXPECT_EQ(roundTripBinary(std::numeric_limits<short>::min()), std::numeric_limits<short>::min());
  EXPECT_EQ(roundTripBinary(static_cast<unsigned short>(65535)), 65535);
  EXPECT_EQ(roundTripBinary(-123456789), -123456789);
  EXPECT_EQ(roundTripBinary(4000000000u), 4000000000u);
  EXPECT_EQ(roundTripBinary(std::numeric_limits<long>::min()), std::numeric_limits<long>::min());
  EXPECT_EQ(roundTripBinary(std::numeric_limits<unsigned long>::max()), std::numeric_limits<unsigned long>::max());
  EXPECT_EQ(roundTripBinary(-9000000000000000000LL), -9000000000000000000LL);
  EXPECT_EQ(roundTripBinary(18000000000000000000ULL), 18000000000000000000ULL);
  EXPECT_EQ(roundTripBinary(0.1f), 0.1f);
  EXPECT_EQ(roundTripBinary(-1.0 / 3.0), -1.0 / 3.0);
  EXPECT_EQ(roundTripBinary(1.0L / 3.0L), 1.0L / 3.0L);
  EXPECT_TRUE(std::isnan(roundTripBinary(std::numeric_limits<double>::quiet_NaN())));
  EXPECT_EQ(roundTripBinary(kRunning), kRunning);
}

TEST(OprosArchive, RoundTripsStrings) {
  EXPECT_EQ(roundTripBinary(std::string()), "");
  const std::string with_nul("a\0b\xff", 4);
  EXPECT_EQ(roundTripBinary(with_nul), with_nul);
  EXPECT_EQ(roundTripBinary(std::string(200000, 'x')), std::string(200000, 'x'));
  EXPECT_EQ(roundTripBinary(std::wstring(L"\x263A wide")), L"\x263A wide");
}

TEST(OprosArchive, RoundTripsStlContainers) {
  EXPECT_EQ(roundTripBinary(std::vector<int>{3, 1, 2}), (std::vector<int>{3, 1, 2}));
  EXPECT_EQ(roundTripBinary(std::vector<bool>{true, false, true}), (std::vector<bool>{true, false, true}));
  EXPECT_EQ(roundTripBinary(std::list<std::string>{"a", "bc"}), (std::list<std::string>{"a", "bc"}));
  EXPECT_EQ(roundTripBinary(std::deque<double>{1.5}), (std::deque<double>{1.5}));
  EXPECT_EQ(roundTripBinary(std::set<int>{5, 4}), (std::set<int>{4, 5}));
  EXPECT_EQ(roundTripBinary(std::multiset<int>{1, 1}), (std::multiset<int>{1, 1}));
  const std::map<std::string, std::vector<double>> map{{"a", {1.0}}, {"b", {}}};
  EXPECT_EQ(roundTripBinary(map), map);
  const std::multimap<int, std::string> multimap{{1, "x"}, {1, "y"}};
  EXPECT_EQ(roundTripBinary(multimap), multimap);
  const std::unordered_map<std::string, int> hashed{{"k", 1}};
  EXPECT_EQ(roundTripBinary(hashed), hashed);
  EXPECT_EQ(roundTripBinary(std::array<int, 3>{7, 8, 9}), (std::array<int, 3>{7, 8, 9}));
  EXPECT_EQ(roundTripBinary(std::pair<int, std::string>{1, "p"}), (std::pair<int, std::string>{1, "p"}));
  EXPECT_EQ(roundTripBinary(std::complex<double>(1, -2)), std::complex<double>(1, -2));
  EXPECT_EQ(roundTripBinary(std::vector<std::vector<int>>{{1}, {2, 3}}), (std::vector<std::vector<int>>{{1}, {2, 3}}));

  const std::valarray<double> values{1.0, 2.0, 3.0};
  const std::valarray<double> loaded_values = roundTripBinary(values);
  ASSERT_EQ(loaded_values.size(), 3u);
  EXPECT_EQ(loaded_values[2], 3.0);

  std::stack<int> stack;
  stack.push(1);
  stack.push(2);
  std::stack<int> loaded_stack = roundTripBinary(stack);
  EXPECT_EQ(loaded_stack, stack);
  std::queue<int> queue;
  queue.push(3);
  queue.push(4);
  EXPECT_EQ(roundTripBinary(queue), queue);
  std::priority_queue<int> heap;
  heap.push(1);
  heap.push(9);
  heap.push(5);
  std::priority_queue<int> loaded_heap = roundTripBinary(heap);
  ASSERT_EQ(loaded_heap.size(), 3u);
  EXPECT_EQ(loaded_heap.top(), 9);
}

TEST(OprosArchive, RoundTripsCArraysAndNamedValues) {
  std::stringstream stream;
  opros::archive::binary_oarchive out(&stream);
  int numbers[3] = {1, 2, 3};
  double gain = 0.5;
  out << numbers << OPROS_SERIALIZATION_NVP(gain);
  opros::archive::binary_iarchive in(&stream);
  int loaded[3] = {};
  double loaded_gain = 0;
  in >> loaded >> OPROS_SERIALIZATION_MAKE_NVP(gain, loaded_gain);
  EXPECT_EQ(loaded[2], 3);
  EXPECT_EQ(loaded_gain, 0.5);
}

TEST(OprosArchive, RoundTripsUserTypesEachWayOprosAllows) {
  PersonData person(42, "kim");
  PersonData loaded = roundTripBinary(person);
  EXPECT_EQ(loaded.getAge(), 42);
  EXPECT_EQ(loaded.getName(), "kim");

  const std::vector<PersonData> people{{1, "a"}, {2, "b"}};
  std::vector<PersonData> loaded_people = roundTripBinary(people);
  ASSERT_EQ(loaded_people.size(), 2u);
  EXPECT_EQ(loaded_people[1].getName(), "b");

  Waypoint waypoint{1.5, -2.5};
  Waypoint loaded_waypoint = roundTripBinary(waypoint);
  EXPECT_EQ(loaded_waypoint.y, -2.5);

  Gains gains{2.0, 0.1};
  Gains loaded_gains = roundTripBinary(gains);
  EXPECT_EQ(loaded_gains.kp, 2.0);
  EXPECT_EQ(loaded_gains.ki, 0.1);

  static_assert(has_opros_serialization<PersonData>::value);
  static_assert(!has_opros_serialization<Waypoint>::value);
}

TEST(OprosArchive, TruncatedStreamThrowsAndNeverOverreads) {
  const std::string whole = savedBinary(std::vector<int>{1, 2, 3, 4, 5});
  for (std::size_t cut = 0; cut < whole.size(); ++cut) {
    std::istringstream stream(whole.substr(0, cut));
    opros::archive::binary_iarchive in(&stream);
    std::vector<int> loaded;
    EXPECT_THROW(in >> loaded, opros::archive::archive_format_exception) << "cut at " << cut;
  }
  std::istringstream stream(whole.substr(0, whole.size() - 2));
  opros::archive::binary_iarchive in(&stream);
  std::vector<int> loaded{7};
  try {
    in >> loaded;
    FAIL() << "a truncated stream did not throw";
  } catch (const opros::archive::archive_format_exception& e) {
    EXPECT_NE(std::string(e.what()).find("the stream ends at byte"), std::string::npos) << e.what();
  }
  EXPECT_EQ(loaded, (std::vector<int>{7})) << "a failed load replaced the container";
}

TEST(OprosArchive, AnotherTypeInTheStreamThrowsATypeError) {
  std::istringstream stream(savedBinary(2.5));
  opros::archive::binary_iarchive in(&stream);
  int wrong = 0;
  try {
    in >> wrong;
    FAIL() << "a double read as an int did not throw";
  } catch (const opros::archive::archive_type_exception& e) {
    EXPECT_STREQ(e.what(), "opros binary archive: expected int at byte 0, found double");
  }
}

TEST(OprosArchive, ForeignOrCorruptBytesThrowWithoutAHugeAllocation) {
  std::istringstream text("hello");
  opros::archive::binary_iarchive in(&text);
  std::string loaded;
  EXPECT_THROW(in >> loaded, opros::archive::archive_type_exception);

  // A string claiming 2^62 bytes, followed by three.
  std::string corrupt = "S";
  const std::uint64_t huge = std::uint64_t{1} << 62;
  for (int i = 0; i < 8; ++i) corrupt += static_cast<char>((huge >> (8 * i)) & 0xFF);
  corrupt += "abc";
  std::istringstream stream(corrupt);
  opros::archive::binary_iarchive corrupt_in(&stream);
  EXPECT_THROW(corrupt_in >> loaded, opros::archive::archive_format_exception);

  std::istringstream bad_bool(std::string("b\x07", 2));
  opros::archive::binary_iarchive bool_in(&bad_bool);
  bool flag = false;
  EXPECT_THROW(bool_in >> flag, opros::archive::archive_format_exception);
}

TEST(OprosArchive, FixedSizeTargetsRejectAnotherLength) {
  std::istringstream stream(savedBinary(std::vector<int>{1, 2}));
  opros::archive::binary_iarchive in(&stream);
  std::array<int, 3> three{};
  EXPECT_THROW(in >> three, opros::archive::archive_array_size_exception);
}

TEST(OprosArchive, RawArchiveRoundTripsWithoutTagsAndStillDetectsTheEnd) {
  const PersonData loaded = roundTrip<opros::archive::raw_oarchive, opros::archive::raw_iarchive>(PersonData(3, "raw"));
  EXPECT_EQ(const_cast<PersonData&>(loaded).getName(), "raw");

  std::stringstream stream;
  opros::archive::raw_oarchive out(&stream);
  out << 1;
  EXPECT_EQ(stream.str().size(), sizeof(int)) << "the raw archive wrote a tag";
  opros::archive::raw_iarchive in(&stream);
  long long too_wide = 0;
  EXPECT_THROW(in >> too_wide, opros::archive::archive_format_exception);
}

TEST(OprosArchive, StringArchiveRoundTripsInDecimalAndHex) {
  using Out = opros::archive::string_oarchive;
  using In = opros::archive::string_iarchive;
  for (int mode : {0, 1}) {
    EXPECT_EQ((roundTrip<Out, In>(-1.0 / 3.0, mode)), -1.0 / 3.0) << "mode " << mode;
    EXPECT_EQ((roundTrip<Out, In>(0.1f, mode)), 0.1f);
    EXPECT_EQ((roundTrip<Out, In>(std::numeric_limits<long long>::min(), mode)), std::numeric_limits<long long>::min());
    EXPECT_EQ((roundTrip<Out, In>(std::string("two words:\n"), mode)), "two words:\n");
    const std::map<std::string, std::vector<int>> map{{"k", {-1, 255}}};
    EXPECT_EQ((roundTrip<Out, In>(map, mode)), map);
    EXPECT_EQ((roundTrip<Out, In>(std::wstring(L"w\x263A"), mode)), L"w\x263A");
  }
  std::ostringstream text;
  Out out(&text, 1);
  out << 255 << true;
  EXPECT_EQ(text.str(), "i0xff b1 ");
}

TEST(OprosArchive, StringArchiveRejectsMalformedText) {
  std::istringstream not_a_number("iabc ");
  opros::archive::string_iarchive in(&not_a_number);
  int value = 0;
  EXPECT_THROW(in >> value, opros::archive::archive_format_exception);

  std::istringstream out_of_range("h300 ");
  opros::archive::string_iarchive range_in(&out_of_range);
  unsigned char byte = 0;
  EXPECT_THROW(range_in >> byte, opros::archive::archive_format_exception);

  std::istringstream short_string("S10:abc");
  opros::archive::string_iarchive string_in(&short_string);
  std::string text;
  EXPECT_THROW(string_in >> text, opros::archive::archive_format_exception);
}

TEST(OprosArchive, BinaryBlocksAndTheFactoryRoundTrip) {
  BinaryArchiveFactory factory;
  std::stringstream stream;
  opros::archive::oarchive* out = factory.getOutputArchive(&stream);
  opros::binary blob;
  blob.resize(3);
  blob.data()[0] = 'x';
  blob.data()[2] = '\xff';
  *out << blob;
  factory.release(out);

  opros::archive::iarchive* in = factory.getInputArchive(&stream);
  opros::binary loaded;
  *in >> loaded;
  factory.release(in);
  ASSERT_EQ(loaded.size(), 3ul);
  EXPECT_EQ(loaded.data()[0], 'x');
  EXPECT_EQ(loaded.data()[2], '\xff');
}

// ---- device types ----

TEST(OprosDeviceProperty, IsOneTypeForBothFlavours) {
  static_assert(std::is_same_v<Property, OPRoS::Property>);
  std::map<std::string, std::string> from_profile{{"ApiName", "Hokuyo.so"}, {"Period", "0.1"}};
  kitech_parameter.SetProperty(from_profile);  // as KITECH's onInitialize does
  EXPECT_TRUE(kitech_parameter.FindName("Period"));
  EXPECT_EQ(atof(kitech_parameter.GetValue("Period").c_str()), 0.1);  // NOLINT(cert-err34-c): as KITECH's code reads it
  EXPECT_EQ(kitech_parameter.GetValue("Missing"), "");
  EXPECT_FALSE(kitech_parameter.FindName("Missing")) << "GetValue added the name";

  OPRoS::Property parameter;
  EXPECT_EQ(parameter.status, static_cast<ReturnType>(OPROS_SUCCESS));
  parameter.SetValue("PortName", "COM3");
  parameter.status = OPROS_FIND_PROPERTY_ERROR;
  OPRoS::Property loaded = roundTripBinary(parameter);
  EXPECT_EQ(loaded.GetValue("PortName"), "COM3");
  EXPECT_EQ(loaded.status, static_cast<ReturnType>(OPROS_FIND_PROPERTY_ERROR));
  EXPECT_EQ(loaded.GetProperty().size(), 1u);
  EXPECT_EQ(getTypeName(&loaded), "Property");
}

TEST(OprosDeviceApiTypes, Float64ArrayWorksAsLaserScannerTestCompUsesIt) {
  std::vector<OPRoS::Float64Array> vval(1);
  vval[0].data = {0.5, 1.5};
  OPRoS::Float64Array fval;
  fval = vval[0].data;  // a vector<double> converts, as in its onExecute
  EXPECT_EQ(fval.data.size(), 2u);
  EXPECT_EQ(fval.status, static_cast<ReturnType>(OPROS_SUCCESS));

  vval[0].status = OPROS_CALL_API_ERROR;
  std::vector<OPRoS::Float64Array> loaded = roundTripBinary(vval);
  ASSERT_EQ(loaded.size(), 1u);
  EXPECT_EQ(loaded[0].data, (std::vector<double>{0.5, 1.5}));
  EXPECT_EQ(loaded[0].status, static_cast<ReturnType>(OPROS_CALL_API_ERROR));
}

TEST(OprosDeviceApiTypes, ValueWrappersCarryStatusDataAndOprosNames) {
  OPRoS::Bool flag = true;
  EXPECT_TRUE(flag.data);
  OPRoS::Int16 small = static_cast<std::int16_t>(-3);
  EXPECT_EQ(roundTripBinary(small).data, -3);
  OPRoS::String text = std::string("hi");
  EXPECT_EQ(roundTripBinary(text).data, "hi");
  OPRoS::StringArray words(std::vector<std::string>{"a"});
  EXPECT_EQ(roundTripBinary(words).data.size(), 1u);
  EXPECT_EQ(getTypeName(&flag), "Bool");
  EXPECT_EQ(getTypeName(&small), "Int16");
  EXPECT_EQ(getTypeName(static_cast<OPRoS::UInt64Array*>(nullptr)), "UInt64Array");
  EXPECT_EQ(getTypeName(static_cast<OPRoS::Float32*>(nullptr)), "Float32");
}

TEST(OprosDeviceApiTypes, MotionRecordsRoundTripWithTheirStatus) {
  OPRoS::MobileVelocityData velocity(0.3, 0.0, 0.1);
  velocity.status = OPROS_API_EXECUTING;
  const OPRoS::MobileVelocityData loaded = roundTripBinary(velocity);
  EXPECT_EQ(loaded.x, 0.3);
  EXPECT_EQ(loaded.theta, 0.1);
  EXPECT_EQ(loaded.status, static_cast<ReturnType>(OPROS_API_EXECUTING));
  EXPECT_EQ(getTypeName(&velocity), "MobileVelocityData");

  OPRoS::CameraData image;
  image.width = 2;
  image.data = {1, 2, 3};
  EXPECT_EQ(roundTripBinary(image).data, (std::vector<std::uint8_t>{1, 2, 3}));
}

TEST(OprosDeviceObjectLocation, IsGlobalAndBehavesAsIn2012) {
  static_assert(std::is_same_v<ObjectLocation, OPRoS::ObjectLocation>);
  ObjectLocation origin(0, 0, 0);
  ObjectLocation polar(2.0, M_PI / 2);
  EXPECT_NEAR(polar.x, 0.0, 1e-12);
  EXPECT_NEAR(polar.y, 2.0, 1e-12);
  EXPECT_DOUBLE_EQ(origin.Distance(polar), 2.0);
  ObjectLocation turned(1, 0, 0);
  turned.Rotate(M_PI);
  EXPECT_NEAR(turned.x, -1.0, 1e-12);
  EXPECT_NEAR(turned.theta, M_PI, 1e-12);
  const ObjectLocation d = diff(ObjectLocation(0, 0, 3.0), ObjectLocation(0, 0, -3.0));
  EXPECT_NEAR(d.theta, 6.0 - 2 * M_PI, 1e-12) << "the heading difference was not wrapped";

  std::vector<ObjectLocation> path{ObjectLocation(1, 2, 0.5)};
  EXPECT_EQ(roundTripBinary(path)[0].y, 2.0);
  EXPECT_EQ(getTypeName(&path), "std::vector<ObjectLocation>");
}

TEST(OprosDevice2012Records, OperatorsLeaveTheirOperandsUnchanged) {
  const ObjectPosition a(1, 2, 3, 0, 0, 0);
  const ObjectPosition b(1, 1, 1, 0, 0, 0);
  const ObjectPosition sum = a + b;
  EXPECT_EQ(sum.x, 2.0);
  EXPECT_EQ(sum.z, 4.0);
  EXPECT_EQ(a.x, 1.0);
  GpsData fix(37.5, 127.0, "12:00", 0.0);
  EXPECT_EQ(roundTripBinary(fix).time, "12:00");
  EXPECT_EQ(roundTripBinary(fix).status, static_cast<ReturnType>(OPROS_SUCCESS));
}

TEST(OprosDeviceMath, ConvertsAnglesAndWrapsDifferences) {
  EXPECT_DOUBLE_EQ(RAD2DEG(M_PI), 180.0);
  EXPECT_DOUBLE_EQ(DEG2RAD(90.0), M_PI / 2);
  EXPECT_EQ(DeltaDeg(170, -170), -20);
  EXPECT_NEAR(DeltaRad(0.1, 2 * M_PI), 0.1, 1e-12);
  EXPECT_EQ(Distance(0, 0, 3, 4), 5);
  EXPECT_DOUBLE_EQ(Distance(0.0, 0.0, 3.0, 4.0), 5.0);
  EXPECT_TRUE(IsNum(1.0));
  EXPECT_FALSE(IsNum(NaN));
}

TEST(OprosDeviceNames, StdNamesAreUsableUnqualified) {
  kitech_path[1][2] = 4.0;
  kitech_map["a"] = "b";
  EXPECT_EQ(kitech_path[1][2], 4.0);
  EXPECT_EQ(kitech_map.size(), 1u);
  string word = "ok";
  EXPECT_EQ(word, "ok");
}

TEST(OprosDevicePrintMessage, PrintsLikePrintf) {
  testing::internal::CaptureStdout();
  PrintMessage("%s::onInitialize() %d\n", "Planner", 3);
  std::fflush(stdout);
  EXPECT_EQ(testing::internal::GetCapturedStdout(), "Planner::onInitialize() 3\n");
}

}  // namespace
