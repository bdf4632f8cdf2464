// The nucleus's state: what a step carries to the next one as physics and what the caller sets
// or reads between steps. The state hash covers the positions and velocities (bit patterns);
// the rest decides which particles the next step integrates (sleep), which bonds still act,
// and holds the caller's inputs and the last step's outputs. Sizes: N particles, B bonds.
//
// Not here, though kept between steps, are the workspace's caches (Verlet rows, wall-sum cache,
// static-collider masks): they hold nothing a state needs, but they fix summation orders and
// lag the wall sums within their tolerance, so a bit-identical replay must also start from the
// same workspace (a Nucleus built the same way and stepped the same way).
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

#include "engine/core/types.hpp"

namespace acdr {

/// Bonds made during the run between touching particles of a re-bonding material (cohesion,
/// MaterialConfig::rebond_time_s), in a pool of C slots fixed at build (empty when no material
/// re-bonds). In the pairs and Verlet rows a re-formed bond in slot s is bond index B + s (B:
/// the bonds at build). A broken one frees its slot.
struct ReformedBonds {
  /// Re-formed bonds a particle can hold at once (the 18 lattice neighbours within 1.5 h).
  static constexpr int kPerParticle = 18;
  std::vector<std::int32_t> ij;         // 2C: particles i < j of each slot
  std::vector<double> rest;             // C, rest length (the distance when made), m
  std::vector<double> k;                // C, stiffness, N/m
  std::vector<double> break_hi2;        // C, (L + delta)^2, m^2
  std::vector<double> break_lo2;        // C, (L - delta)^2, m^2 (0: never)
  std::vector<std::uint8_t> alive;      // C, 1 while in use
  std::vector<std::int32_t> free;       // C: [0, free_count) the free slots (a stack)
  std::size_t free_count = 0;
  std::vector<std::int32_t> of;         // kPerParticle N: each particle's slots, -1 unused
  std::vector<double> settled_s;        // N: time at rest relative to its neighbours, s
  std::size_t made = 0;                 // bonds re-formed so far
  std::size_t capacity() const { return rest.size(); }
};

struct NucleusState {
  // ---- Hashed (state_hash) ----
  std::vector<Vec3> x;  // N, positions, m
  std::vector<Vec3> v;  // N, velocities, m/s

  // ---- The caller's inputs, kept until changed ----
  std::vector<Vec3> f_ext;    // N, external forces, N; added every step
  std::vector<Vec3> fixed_v;  // N, prescribed velocity of fixed particles, m/s

  // ---- Kinematic particles: the model's fixed ones and those a grasp holds ----
  std::vector<std::uint8_t> kinematic;        // N, 1 = moves at fixed_v, out of the solve
  std::vector<std::int32_t> kinematic_list;   // the kinematic particles, ascending (capacity N)

  // ---- Sleep ----
  std::vector<std::uint8_t> awake;     // N, 1 = integrated in the coming step
  std::vector<std::int32_t> active;    // N: [0, active_count) the awake particles, ascending
  std::size_t active_count = 0;
  std::vector<std::uint16_t> calm;     // N, consecutive calm steps
  std::vector<std::uint8_t> wake_next;  // N, 1 = wakes next step (also listed in wake_list)
  std::vector<std::int32_t> wake_list;  // N: [0, wake_count) particles with wake_next set
  std::size_t wake_count = 0;

  // ---- Bonds ----
  std::vector<std::uint8_t> bond_alive;  // B, 1 while intact
  std::size_t broken_bonds = 0;          // bonds broken so far (re-formed ones included)
  ReformedBonds reformed;

  // ---- Outputs of the last step ----
  std::vector<double> pressure;    // N, Pa, at the end of the last step
  std::vector<Vec3> body_force;    // N, N: force on the moving bodies by particle
  std::vector<Vec3> static_force;  // N, N: force on the gathered static collider by particle
};

}  // namespace acdr
