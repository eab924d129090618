#include <doctest/doctest.h>

#include <string>
#include <thread>
#include <vector>

#include "graph/audio_chunk.h"
#include "graph/packet.h"

using namespace marvin::graph;

namespace {
struct Pose {
  double x = 0, y = 0;
};
}  // namespace
MARVIN_PACKET_TYPE(Pose, "Pose");

TEST_CASE("a packet copy shares the payload and bumps the count") {
  Packet a = Packet::make<std::string>("hello").at(42);
  CHECK(a.use_count() == 1);
  Packet b = a;
  CHECK(a.use_count() == 2);
  CHECK(&a.get<std::string>() == &b.get<std::string>());
  Packet c = b.at(43);
  CHECK(c.timestamp() == 43);
  CHECK(b.timestamp() == 42);
  CHECK(a.use_count() == 3);
  b = Packet();
  c = Packet();
  CHECK(a.use_count() == 1);
}

TEST_CASE("the single owner can move the payload out; a shared payload cannot") {
  AudioChunk chunk;
  chunk.samples.assign(1000, 7);
  Packet p = Packet::make<AudioChunk>(std::move(chunk)).at(0);
  const int16_t* data = p.get<AudioChunk>().samples.data();
  {
    Packet other = p;
    CHECK_THROWS_WITH_AS(p.consume<AudioChunk>(),
                         "cannot move the 'AudioChunk' payload out: 2 packets share it (only a "
                         "single owner may)",
                         PacketError);
    CHECK(other.get<AudioChunk>().samples.size() == 1000);  // nothing changed
  }
  AudioChunk out = p.consume<AudioChunk>();
  CHECK(out.samples.data() == data);  // moved, not copied
  CHECK(p.empty());
}

TEST_CASE("typed access with the wrong type names both registered types") {
  Packet p = Packet::make<Pose>(Pose{1, 2}).at(5);
  CHECK(p.holds<Pose>());
  CHECK_FALSE(p.holds<int64_t>());
  CHECK(std::string(p.type_name()) == "Pose");
  CHECK_THROWS_WITH_AS(p.get<int64_t>(),
                       "packet at timestamp 5 holds 'Pose', but 'int64' was requested",
                       PacketError);
  CHECK_THROWS_WITH_AS(Packet().get<Pose>(), "empty packet: no payload, but 'Pose' was requested",
                       PacketError);
}

TEST_CASE("type identity compares registered names, not addresses") {
  // A type registered in a dlopen()ed library has its own copy of the name string.
  char copy[] = "Pose";
  CHECK(detail::same_type(copy, packet_type_name<Pose>()));
  CHECK_FALSE(detail::same_type("Posture", packet_type_name<Pose>()));
}

TEST_CASE("packets cross threads and are released exactly once") {
  std::vector<Packet> made;
  for (int i = 0; i < 1000; ++i) made.push_back(Packet::make<int64_t>(int64_t{i}).at(i));
  std::thread t([copy = made]() mutable { copy.clear(); });
  made.clear();
  t.join();
  CHECK(made.empty());  // no double free or leak: the sanitizer builds check
}
