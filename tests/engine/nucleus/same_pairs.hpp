// Two steps' particles and pairs compared entry by entry: the same local numbering and the
// same pairs in the same order with the same bits (for tests that build rows two ways).
#pragma once

#include <cstddef>

#include <gtest/gtest.h>

#include "engine/nucleus/nucleus_workspace.hpp"

namespace acdr::test {

/// Expects `a` and `b` (workspaces after build_pairs) to hold the same step particles (awake,
/// a halo of sleepers, outer) and the same pairs, with at least one near pair.
inline void expect_same_pairs(const NucleusWorkspace& a, const NucleusWorkspace& b) {
  const StepParticles& s = a.step;
  const StepParticles& t = b.step;
  ASSERT_EQ(s.awake_end, t.awake_end);
  ASSERT_EQ(s.halo_end, t.halo_end);
  ASSERT_GT(s.halo_end, s.awake_end);  // the sleepers take part through the awake rows
  ASSERT_EQ(s.outer_end, t.outer_end);
  for (std::size_t k = 0; k < s.outer_end; ++k) ASSERT_EQ(s.global[k], t.global[k]) << k;
  const PairList& p = a.pairs;
  const PairList& q = b.pairs;
  ASSERT_FALSE(p.overflow);
  ASSERT_EQ(p.near, q.near);
  ASSERT_EQ(p.far, q.far);
  ASSERT_GT(p.near, 0u);
  EXPECT_EQ(p.near_awake, q.near_awake);
  EXPECT_EQ(p.far_awake, q.far_awake);
  auto same = [&](std::size_t k) {
    EXPECT_EQ(p.i[k], q.i[k]) << k;
    EXPECT_EQ(p.j[k], q.j[k]) << k;
    EXPECT_EQ(p.bond[k], q.bond[k]) << k;
    EXPECT_EQ(p.r[k], q.r[k]) << k;
    EXPECT_EQ(p.n[k], q.n[k]) << k;
  };
  for (std::size_t k = 0; k < p.near; ++k) same(k);
  for (std::size_t k = p.cap - p.far; k < p.cap; ++k) same(k);
}

}  // namespace acdr::test
