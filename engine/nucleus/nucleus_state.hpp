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

struct NucleusState {
  // ---- Hashed (state_hash) ----
  std::vector<Vec3> x;  // N, positions, m
  std::vector<Vec3> v;  // N, velocities, m/s

  // ---- The caller's inputs, kept until changed ----
  std::vector<Vec3> f_ext;    // N, external forces, N; added every step
  std::vector<Vec3> fixed_v;  // N, prescribed velocity of fixed particles, m/s

  // ---- Sleep ----
  std::vector<std::uint8_t> awake;     // N, 1 = integrated in the coming step
  std::vector<std::int32_t> active;    // N: [0, active_count) the awake particles, ascending
  std::size_t active_count = 0;
  std::vector<std::uint16_t> calm;     // N, consecutive calm steps
  std::vector<std::uint8_t> wake_next;  // N, 1 = wakes next step (also listed in wake_list)
  std::vector<std::int32_t> wake_list;  // N: [0, wake_count) particles with wake_next set
  std::size_t wake_count = 0;
  std::vector<std::uint8_t> release;   // N, 1: a contact pulled last step; skip it once

  // ---- Bonds ----
  std::vector<std::uint8_t> bond_alive;  // B, 1 while intact
  std::size_t broken_bonds = 0;

  // ---- Outputs of the last step ----
  std::vector<double> pressure;    // N, Pa, at the end of the last step
  std::vector<Vec3> body_force;    // N, N: force on the moving bodies by particle
  std::vector<Vec3> static_force;  // N, N: force on the gathered static collider by particle
};

}  // namespace acdr
