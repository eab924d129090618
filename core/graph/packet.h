// Packet: an immutable, type-erased payload with a timestamp.
//
// A Packet is a small handle (pointer + timestamp + flags) to a reference-counted payload.
// Copying a Packet bumps the count; the payload is destroyed when the last handle goes away.
// The payload is never modified after creation, so handles may be read from any thread.
// The only exception is consume(): the single owner of a payload may move it out.
//
// Type identity uses the *registered name* of the payload type, not typeid, so a packet made
// in a skill loaded with dlopen() is recognised by the host as long as both register the
// same name. Register a type once, at global scope, next to its definition:
//
//   struct Detection { float score; };
//   MARVIN_PACKET_TYPE(Detection, "Detection");
//
// Graph contracts name port types with these same strings.
//
// Timestamps are microseconds of stream time (for audio: the time of the first sample), they
// increase strictly along each stream. The `discontinuous` flag is set by the framework on
// the first packet a consumer sees after packets were dropped (or after a latch reopened):
// whatever state a node accumulated across packets should be reset.
//
// Thread safety: distinct Packet handles may be used concurrently, even when they share a
// payload. A single handle is not synchronised (like std::shared_ptr).
#pragma once

#include <atomic>
#include <climits>
#include <cstdint>
#include <cstring>
#include <stdexcept>
#include <string>
#include <utility>

#include "graph/packet_pool.h"

namespace marvin::graph {

// Microseconds of stream time.
using Timestamp = int64_t;
// A packet that was never stamped.
inline constexpr Timestamp kTimestampUnset = INT64_MIN;
// The smallest timestamp a packet may carry.
inline constexpr Timestamp kTimestampMin = INT64_MIN + 1;
// The bound of a stream that will never carry another packet.
inline constexpr Timestamp kTimestampDone = INT64_MAX;

// Specialised by MARVIN_PACKET_TYPE; a compile error here means the type was not registered.
template <typename T>
struct PacketTypeName;

// The registered name of T, e.g. "AudioChunk".
template <typename T>
constexpr const char* packet_type_name() {
  return PacketTypeName<T>::value;
}

// Thrown by Packet::get/consume when the payload has another type, or is empty or shared.
class PacketError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

namespace detail {

class Payload {
 public:
  explicit Payload(const char* type_name) : type_name_(type_name) {}
  virtual ~Payload() = default;
  Payload(const Payload&) = delete;
  Payload& operator=(const Payload&) = delete;

  static void* operator new(std::size_t size) { return pool_allocate(size); }
  static void operator delete(void* block, std::size_t size) { pool_free(block, size); }

  const char* type_name() const { return type_name_; }
  void acquire() { refs_.fetch_add(1, std::memory_order_relaxed); }
  void release() {
    if (refs_.fetch_sub(1, std::memory_order_acq_rel) == 1) delete this;
  }
  uint32_t use_count() const { return refs_.load(std::memory_order_acquire); }

 private:
  const char* type_name_;
  std::atomic<uint32_t> refs_{1};
};

template <typename T>
class TypedPayload final : public Payload {
 public:
  template <typename... Args>
  explicit TypedPayload(Args&&... args)
      : Payload(packet_type_name<T>()), value(std::forward<Args>(args)...) {}
  T value;
};

inline bool same_type(const char* a, const char* b) {
  return a == b || std::strcmp(a, b) == 0;
}

[[noreturn]] void throw_type_error(const char* held, const char* wanted, Timestamp ts);
[[noreturn]] void throw_empty_error(const char* wanted);
[[noreturn]] void throw_shared_error(const char* type, uint32_t owners);

}  // namespace detail

class Packet {
 public:
  // An empty packet: no payload, timestamp unset.
  Packet() = default;

  // Makes a packet holding T constructed from `args`, with an unset timestamp.
  template <typename T, typename... Args>
  static Packet make(Args&&... args) {
    Packet p;
    p.payload_ = new detail::TypedPayload<T>(std::forward<Args>(args)...);
    return p;
  }

  Packet(const Packet& other)
      : payload_(other.payload_), timestamp_(other.timestamp_), discontinuous_(other.discontinuous_) {
    if (payload_) payload_->acquire();
  }
  Packet(Packet&& other) noexcept
      : payload_(std::exchange(other.payload_, nullptr)),
        timestamp_(other.timestamp_),
        discontinuous_(other.discontinuous_) {}
  Packet& operator=(const Packet& other) {
    if (this != &other) {
      if (other.payload_) other.payload_->acquire();
      reset();
      payload_ = other.payload_;
      timestamp_ = other.timestamp_;
      discontinuous_ = other.discontinuous_;
    }
    return *this;
  }
  Packet& operator=(Packet&& other) noexcept {
    if (this != &other) {
      reset();
      payload_ = std::exchange(other.payload_, nullptr);
      timestamp_ = other.timestamp_;
      discontinuous_ = other.discontinuous_;
    }
    return *this;
  }
  ~Packet() { reset(); }

  // A handle to the same payload stamped with `ts` (a reference-count bump, no copy).
  Packet at(Timestamp ts) const& {
    Packet p(*this);
    p.timestamp_ = ts;
    return p;
  }
  Packet at(Timestamp ts) && {
    timestamp_ = ts;
    return std::move(*this);
  }

  bool empty() const { return payload_ == nullptr; }
  Timestamp timestamp() const { return timestamp_; }
  // True on the first packet delivered after a gap (drops upstream, a reopened latch).
  bool discontinuous() const { return discontinuous_; }
  void set_discontinuous(bool value) { discontinuous_ = value; }
  // Registered type name of the payload, or "" for an empty packet.
  const char* type_name() const { return payload_ ? payload_->type_name() : ""; }
  // How many handles share the payload (0 when empty).
  uint32_t use_count() const { return payload_ ? payload_->use_count() : 0; }

  template <typename T>
  bool holds() const {
    return payload_ && detail::same_type(payload_->type_name(), packet_type_name<T>());
  }

  // The payload as T. Throws PacketError naming both types if the payload is not a T (or the
  // packet is empty). The reference lives as long as any handle to the payload.
  template <typename T>
  const T& get() const {
    check<T>();
    return static_cast<const detail::TypedPayload<T>*>(payload_)->value;
  }

  // Moves the payload out and leaves this packet empty. Only the single owner may do this:
  // throws PacketError if other handles share the payload or the type is wrong.
  template <typename T>
  T consume() {
    check<T>();
    const uint32_t owners = payload_->use_count();
    if (owners != 1) detail::throw_shared_error(payload_->type_name(), owners);
    T out = std::move(static_cast<detail::TypedPayload<T>*>(payload_)->value);
    reset();
    return out;
  }

 private:
  template <typename T>
  void check() const {
    if (!payload_) detail::throw_empty_error(packet_type_name<T>());
    if (!detail::same_type(payload_->type_name(), packet_type_name<T>())) {
      detail::throw_type_error(payload_->type_name(), packet_type_name<T>(), timestamp_);
    }
  }
  void reset() {
    if (payload_) std::exchange(payload_, nullptr)->release();
  }

  detail::Payload* payload_ = nullptr;
  Timestamp timestamp_ = kTimestampUnset;
  bool discontinuous_ = false;
};

}  // namespace marvin::graph

// Registers `Type` under `Name` (a string literal). Use at global scope, once per type.
#define MARVIN_PACKET_TYPE(Type, Name)                     \
  template <>                                              \
  struct marvin::graph::PacketTypeName<Type> {             \
    static constexpr const char* value = Name;             \
  }

MARVIN_PACKET_TYPE(bool, "bool");
MARVIN_PACKET_TYPE(int64_t, "int64");
MARVIN_PACKET_TYPE(double, "double");
MARVIN_PACKET_TYPE(std::string, "string");
