// OPRoSTypes.h — keel's own, from-scratch OPRoS-compatible version of OPRoS's basic types.
//
// The enumerations of ports and lifecycle states, opros_assert, and `opros_any`, the
// type-erased value holder that data ports hand out (`opros_any *p = port.pop();`), with its
// casts and the SAFE_CASTING/ANY_CASTING/UNSAFE_ANY_CASTING macros, plus `opros_params`, an
// opros_any that an archive can also write and read. OPRoS code relies on this header for
// <sstream>, <iostream>, <string>, <map>, <vector>, <list> and <cstring> too. opros_any is a
// value: one object is not shared between threads without a lock, copies are independent.
#pragma once

#include <cstring>
#include <iostream>
#include <list>
#include <map>
#include <memory>
#include <sstream>
#include <string>
#include <type_traits>
#include <typeinfo>
#include <utility>
#include <vector>

#include "AssertException.h"
#include "ReturnType.h"
#include "archive/opros_iarchive.h"
#include "archive/opros_oarchive.h"
#include "archive/opros_type_info.h"

typedef enum { OPROS_MT_PROVIDED, OPROS_MT_REQUIRED, OPROS_MT_REMOTE } MethodType;

typedef enum { OPROS_SERVICE, OPROS_EVENT, OPROS_DATA, OPROS_REMOTE_DATA } PortType;

typedef enum { OPROS_FIFO, OPROS_LIFO, OPROS_UFIFO, OPROS_LAST } DataPortPolicy;

typedef enum {
  OPROS_CS_CREATED,
  OPROS_CS_READY,
  OPROS_CS_ACTIVE,
  OPROS_CS_INACTIVE,
  OPROS_CS_ERROR,
  OPROS_CS_DESTROYED
} LifecycleState;

typedef enum { OPROS_DATA_PORT_INPUT, OPROS_DATA_PORT_OUTPUT } DataPortRole;

typedef enum { OPROS_EVENT_PORT_INPUT, OPROS_EVENT_PORT_OUTPUT } EventPortRole;

typedef enum { OPROS_SERVICE_PORT_REQUIRED, OPROS_SERVICE_PORT_PROVIDED } ServicePortRole;

#define DEFAULT_QUEUE_LIMIT 15

// Throws AssertException (a std::exception) naming the condition, file and line when x is false.
#ifndef opros_assert
#define opros_assert(x)                                        \
  do {                                                         \
    if (!(x)) throw ::AssertException(#x, __FILE__, __LINE__); \
  } while (false)
#endif

// opros_any_cast<T>(opros_any&) on a value that does not hold a T.
class bad_opros_any_cast : public std::bad_cast {
 public:
  bad_opros_any_cast(const std::string& held, const std::string& wanted)
      : message_("opros_any_cast: the value holds " + held + ", not " + wanted) {}
  const char* what() const noexcept override { return message_.c_str(); }

 private:
  std::string message_;
};

class opros_any;
template <typename T>
T* opros_any_cast(opros_any* operand) noexcept;
template <typename T>
T* unsafe_opros_any_cast(opros_any* operand) noexcept;

class opros_any {
 public:
  opros_any() noexcept = default;

  // Holds a copy of value (moved in from an rvalue).
  template <typename T>
  requires(!std::is_same_v<std::decay_t<T>, opros_any>)
      opros_any(T&& value)  // NOLINT(google-explicit-constructor): OPRoS code converts implicitly
      : content_(std::make_unique<holder<std::decay_t<T>>>(std::forward<T>(value))) {}

  opros_any(const opros_any& other) : content_(other.content_ ? other.content_->clone() : nullptr) {}
  opros_any(opros_any&& other) noexcept = default;

  opros_any& operator=(const opros_any& rhs) {
    opros_any(rhs).swap(*this);
    return *this;
  }
  opros_any& operator=(opros_any&& rhs) noexcept = default;

  template <typename T>
  requires(!std::is_same_v<std::decay_t<T>, opros_any>) opros_any& operator=(T&& rhs) {
    opros_any(std::forward<T>(rhs)).swap(*this);
    return *this;
  }

  ~opros_any() = default;

  opros_any& swap(opros_any& rhs) noexcept {
    content_.swap(rhs.content_);
    return *this;
  }

  bool empty() const noexcept { return !content_; }

  // The held type; typeid(void) when empty.
  const std::type_info& type() const noexcept { return content_ ? content_->type() : typeid(void); }

  // The held type's OPRoS name (getTypeName), e.g. "std::string"; "void" when empty.
  std::string getTypeName() const { return content_ ? content_->type_name() : "void"; }

 private:
  struct holder_base {
    virtual ~holder_base() = default;
    virtual std::unique_ptr<holder_base> clone() const = 0;
    virtual const std::type_info& type() const noexcept = 0;
    virtual std::string type_name() const = 0;
  };

  template <typename T>
  struct holder final : holder_base {
    static_assert(std::is_copy_constructible_v<T>, "opros_any holds copyable values only");

    template <typename U>
    explicit holder(U&& initial) : value(std::forward<U>(initial)) {}

    std::unique_ptr<holder_base> clone() const override { return std::make_unique<holder>(value); }
    const std::type_info& type() const noexcept override { return typeid(T); }
    std::string type_name() const override { return ::getTypeName(static_cast<T*>(nullptr)); }

    T value;
  };

  template <typename T>
  T* held() noexcept {
    using U = std::remove_cv_t<T>;
    if (!content_ || content_->type() != typeid(U)) return nullptr;
    return &static_cast<holder<U>*>(content_.get())->value;
  }

  template <typename T>
  friend T* opros_any_cast(opros_any* operand) noexcept;
  template <typename T>
  friend T* unsafe_opros_any_cast(opros_any* operand) noexcept;

  std::unique_ptr<holder_base> content_;
};

// The held T, or null when operand is null or holds something else.
template <typename T>
T* opros_any_cast(opros_any* operand) noexcept {
  return operand != nullptr ? operand->held<T>() : nullptr;
}

template <typename T>
const T* opros_any_cast(const opros_any* operand) noexcept {
  return opros_any_cast<T>(const_cast<opros_any*>(operand));
}

// A copy of (or, for a reference T, a reference to) the held value; throws bad_opros_any_cast
// when operand holds something else.
template <typename T>
T opros_any_cast(opros_any& operand) {
  using U = std::remove_cvref_t<T>;
  U* held = opros_any_cast<U>(&operand);
  if (held == nullptr) {
    throw bad_opros_any_cast(operand.getTypeName(), ::getTypeName(static_cast<U*>(nullptr)));
  }
  return static_cast<T>(*held);
}

template <typename T>
T opros_any_cast(const opros_any& operand) {
  using U = std::remove_cvref_t<T>;
  const U* held = opros_any_cast<U>(&operand);
  if (held == nullptr) {
    throw bad_opros_any_cast(operand.getTypeName(), ::getTypeName(static_cast<U*>(nullptr)));
  }
  return static_cast<T>(*held);
}

// OPRoS's unchecked cast. keel checks it anyway: null when operand holds something else.
template <typename T>
T* unsafe_opros_any_cast(opros_any* operand) noexcept {
  return operand != nullptr ? operand->held<T>() : nullptr;
}

template <typename T>
const T* unsafe_opros_any_cast(const opros_any* operand) noexcept {
  return unsafe_opros_any_cast<T>(const_cast<opros_any*>(operand));
}

// As OPRoS defines them for g++ (a pointer in, a pointer out for the last two).
#define SAFE_CASTING(a, b) (static_cast<a>(b))
#define ANY_CASTING(a, b) (::unsafe_opros_any_cast<a>(b))
#define UNSAFE_ANY_CASTING(a, b) (::unsafe_opros_any_cast<a>(b))

// An opros_any that an archive can also write (encode) and read (decode): the parameters and
// results of remote service calls. The held type must be serialisable (opros_oarchive.h).
class opros_params {
 public:
  opros_params() noexcept = default;

  template <typename T>
  requires(!std::is_same_v<std::decay_t<T>, opros_params>)
      opros_params(const T& value)  // NOLINT(google-explicit-constructor): as OPRoS
      : content_(std::make_unique<holder<T>>(value)) {}

  opros_params(const opros_params& other) : content_(other.content_ ? other.content_->clone() : nullptr) {}
  opros_params(opros_params&& other) noexcept = default;
  opros_params& operator=(const opros_params& rhs) {
    opros_params(rhs).swap(*this);
    return *this;
  }
  opros_params& operator=(opros_params&& rhs) noexcept = default;
  ~opros_params() = default;

  opros_params& swap(opros_params& rhs) noexcept {
    content_.swap(rhs.content_);
    return *this;
  }

  // Makes an empty holder of T, for a decode to fill.
  template <typename T>
  void setType(const T* = nullptr) {
    if (!content_) content_ = std::make_unique<holder<T>>(T{});
  }

  bool empty() const noexcept { return !content_; }
  const std::type_info& type() const noexcept { return content_ ? content_->type() : typeid(void); }
  std::string getTypeName() const { return content_ ? content_->type_name() : "void"; }

  void encode(opros::archive::oarchive& ar) const {
    if (content_) content_->encode(ar);
  }
  void decode(opros::archive::iarchive& ar) {
    if (content_) content_->decode(ar);
  }

  template <typename T>
  T* get() noexcept {
    if (!content_ || content_->type() != typeid(T)) return nullptr;
    return &static_cast<holder<T>*>(content_.get())->value;
  }

 private:
  struct holder_base {
    virtual ~holder_base() = default;
    virtual std::unique_ptr<holder_base> clone() const = 0;
    virtual const std::type_info& type() const noexcept = 0;
    virtual std::string type_name() const = 0;
    virtual void encode(opros::archive::oarchive& ar) const = 0;
    virtual void decode(opros::archive::iarchive& ar) = 0;
  };

  template <typename T>
  struct holder final : holder_base {
    explicit holder(const T& initial) : value(initial) {}
    std::unique_ptr<holder_base> clone() const override { return std::make_unique<holder>(value); }
    const std::type_info& type() const noexcept override { return typeid(T); }
    std::string type_name() const override { return ::getTypeName(static_cast<T*>(nullptr)); }
    void encode(opros::archive::oarchive& ar) const override { ar << OPROS_SERIALIZATION_MAKE_NVP(param, value); }
    void decode(opros::archive::iarchive& ar) override { ar >> OPROS_SERIALIZATION_MAKE_NVP(param, value); }
    T value;
  };

  std::unique_ptr<holder_base> content_;
};

template <typename T>
T* opros_params_cast(opros_params* operand) noexcept {
  return operand != nullptr ? operand->get<std::remove_cv_t<T>>() : nullptr;
}

template <typename T>
const T* opros_params_cast(const opros_params* operand) noexcept {
  return opros_params_cast<T>(const_cast<opros_params*>(operand));
}

template <typename T>
T opros_params_cast(opros_params& operand) {
  using U = std::remove_cvref_t<T>;
  U* held = opros_params_cast<U>(&operand);
  if (held == nullptr) {
    throw bad_opros_any_cast(operand.getTypeName(), ::getTypeName(static_cast<U*>(nullptr)));
  }
  return static_cast<T>(*held);
}
