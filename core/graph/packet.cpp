#include "graph/packet.h"

namespace marvin::graph::detail {

void throw_type_error(const char* held, const char* wanted, Timestamp ts) {
  std::string when = ts == kTimestampUnset ? std::string("unstamped packet")
                                           : "packet at timestamp " + std::to_string(ts);
  throw PacketError(when + " holds '" + held + "', but '" + wanted + "' was requested");
}

void throw_empty_error(const char* wanted) {
  throw PacketError(std::string("empty packet: no payload, but '") + wanted + "' was requested");
}

void throw_shared_error(const char* type, uint32_t owners) {
  throw PacketError(std::string("cannot move the '") + type + "' payload out: " +
                    std::to_string(owners) + " packets share it (only a single owner may)");
}

}  // namespace marvin::graph::detail
