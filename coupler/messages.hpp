// The coupling messages as data, internal to the coupler library and callable without a socket: decoding a
// frame into an Envelope, and the checks each side applies to every value it receives (docs/protocol.md §5
// states the same ranges). Every function throws CouplingError naming the peer, the step, the field and the
// cause; nothing else escapes (tests/fuzz/fuzz_coupling.cpp feeds them arbitrary bytes).
#pragma once
#include "coupler/participant.hpp"
#include "proto/coupling.pb.h"

#include <cstddef>
#include <cstdint>
#include <string>

namespace undex::coupling {

using wire::Envelope;

// The range of every value received, stated once. A value must be finite and lie in its range.
namespace limits {
constexpr double position = 1e6;      // |x|, |y| ≤ 1e6 m (Hello, Offer, Answer)
constexpr double pressure = 1e13;     // |p_L|, |p_floor|, |geometric|, |p_I| ≤ 1e13 Pa
constexpr double velocity = 1e6;      // |velocity|, |u_L|, |u_I| ≤ 1e6 m/s
constexpr double impedance = 1e12;    // 0 < Z_L ≤ 1e12 Pa s/m
constexpr double area = 1e12;         // 0 < area ≤ 1e12 (m², per radian or per unit depth)
constexpr double end_time = 1e9;      // 0 < Welcome.end_time ≤ 1e9 s
constexpr double normal_error = 1e-9; // | |n| − 1 | ≤ 1e-9
// Δt floor: a step below dt_floor_fraction · end_time is refused (Offer.dt always, Grant.dt unless the
// step ends on an output time). The run driver refuses the same floor (base/run_driver.hpp).
constexpr double dt_floor_fraction = 1e-12;
// |Grant.time − the structure's own time (the sum of the Δt granted before)| ≤ time_tolerance · end_time.
constexpr double time_tolerance = 1e-9;
// A text of the peer (its solver name and version, an Error message, a Stop reason) is quoted in our
// messages and logs with at most this many characters, control characters and bytes that are not UTF-8
// escaped as \xNN.
constexpr std::size_t quoted_name = 100, quoted_message = 1000;
} // namespace limits

// The name of a message body, for errors.
std::string body_name(Envelope::BodyCase b);

// text as it may be quoted: printable, valid UTF-8, at most `limit` characters (then "… (N bytes)").
std::string quote(const std::string& text, std::size_t limit = limits::quoted_message);

// One frame: the message of `step` with body `expected`, or a Heartbeat or a Stop (which the caller
// handles). Throws on bytes that are no Envelope, another protocol version, an Error from the peer (quoted)
// and a message of another step or kind.
Envelope decode(const void* data, std::size_t size, const std::string& peer, std::int64_t step,
                Envelope::BodyCase expected);

// The checks of the fluid side (peer: the structure solver).
// Hello: dimension and α as the fluid's, at least one node, one value per node in every array, positions,
// unit normals and positive areas in range. Returns the interface; peer_name gets "SOLVER VERSION" quoted.
Interface check_hello(const wire::Hello& h, int dimension, int alpha, std::string& peer_name);
// Offer of step: Δt_s finite, ≥ the floor of end_time; positions and velocities per node, in range.
Offer check_offer(const wire::Offer& o, std::size_t nodes, double end_time, const std::string& peer,
                  std::int64_t step);
// Answer of step: p_I, u_I, x, y per node in range; p_I ≥ p_floor.
Answer check_answer(const wire::Answer& a, std::size_t nodes, double p_floor, const std::string& peer,
                    std::int64_t step);

// The checks of the structure side (peer: the fluid solver).
// Welcome: end_time in range. Returns it; peer_name gets "SOLVER VERSION" quoted.
double check_welcome(const wire::Welcome& w, std::string& peer_name);
// Grant of step: 0 < Δt ≤ dt_s (the Δt_s offered), Δt ≥ the floor of end_time unless the step ends on an
// output time and the step before (after_short: it was below the floor) did not (output times closer than
// the floor are merged, so a fluid never needs two such steps in a row); time equal to own_time (the
// structure's time, within the tolerance) and below end_time, time + Δt not after end_time; p_floor and per
// node p_L, u_L, Z_L, geometric in range.
Grant check_grant(const wire::Grant& g, std::size_t nodes, double dt_s, double own_time, double end_time,
                  bool after_short, const std::string& peer, std::int64_t step);

// Either side: the reason of a Stop, quoted.
std::string check_stop(const wire::Stop& s);

} // namespace undex::coupling
