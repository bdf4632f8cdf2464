// Tests of db/uuid.cpp against published vectors (FIPS 180 SHA-1 examples; the RFC 4122 DNS
// namespace example as computed by Python's uuid.uuid5).
#include "db/uuid.hpp"

#include <gtest/gtest.h>

#include <sys/wait.h>
#include <unistd.h>

#include <set>

namespace acdr {
namespace {

TEST(Uuid, Sha1KnownVectors) {
  EXPECT_EQ(sha1_hex(""), "da39a3ee5e6b4b0d3255bfef95601890afd80709");
  EXPECT_EQ(sha1_hex("abc"), "a9993e364706816aba3e25717850c26c9cd0d89d");
  EXPECT_EQ(sha1_hex("abcdbcdecdefdefgefghfghighijhijkijkljklmklmnlmnomnopnopq"),
            "84983e441c3bd26ebaae4aa1f95129e5e54670f1");
  EXPECT_EQ(sha1_hex(std::string(1000000, 'a')), "34aa973cd4c4daa4f61eeb2bdbad27316534016f");
}

TEST(Uuid, Version5MatchesTheReference) {
  EXPECT_EQ(make_uuid_v5("6ba7b810-9dad-11d1-80b4-00c04fd430c8", "www.example.com"),
            std::optional<std::string>("2ed6657d-e927-568b-95e1-2665a8aea6a2"));
  EXPECT_EQ(make_uuid_v5("6BA7B810-9DAD-11D1-80B4-00C04FD430C8", "www.example.com"),
            make_uuid_v5("6ba7b810-9dad-11d1-80b4-00c04fd430c8", "www.example.com"));
  EXPECT_FALSE(make_uuid_v5("not-a-uuid", "x").has_value());
}

TEST(Uuid, Version4IsWellFormedAndUnique) {
  std::set<std::string> seen;
  for (int i = 0; i < 2000; ++i) {
    const std::string u = make_uuid_v4();
    ASSERT_TRUE(is_uuid(u)) << u;
    EXPECT_EQ(u[14], '4') << u;
    EXPECT_NE(std::string("89ab").find(u[19]), std::string::npos) << u;
    EXPECT_TRUE(seen.insert(u).second) << "duplicate " << u;
  }
}

TEST(Uuid, ForkedProcessesMintDifferentIds) {
  // A generator whose state fork() copies would give both children the same next UUID (two
  // programs started from one parent must never share an attempt id).
  (void)make_uuid_v4();
  std::set<std::string> seen;
  for (int i = 0; i < 2; ++i) {
    int fds[2];
    ASSERT_EQ(pipe(fds), 0);
    const pid_t child = fork();
    ASSERT_GE(child, 0);
    if (child == 0) {
      const std::string u = make_uuid_v4();
      _exit(write(fds[1], u.data(), u.size()) == 36 ? 0 : 1);
    }
    close(fds[1]);
    char buffer[36];
    ASSERT_EQ(read(fds[0], buffer, sizeof buffer), 36);
    close(fds[0]);
    int status = 0;
    waitpid(child, &status, 0);
    seen.insert(std::string(buffer, sizeof buffer));
  }
  EXPECT_EQ(seen.size(), 2u);
}

TEST(Uuid, Recognition) {
  EXPECT_TRUE(is_uuid("2ed6657d-e927-568b-95e1-2665a8aea6a2"));
  EXPECT_FALSE(is_uuid("2ed6657d-e927-568b-95e1-2665a8aea6a"));
  EXPECT_FALSE(is_uuid("2ed6657d-e927-568b-95e1-2665a8aea6ag"));
  EXPECT_FALSE(is_uuid("2ed6657de927-568b-95e1-2665a8aea6a2-"));
}

}  // namespace
}  // namespace acdr
