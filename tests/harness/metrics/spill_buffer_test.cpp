// The spill buffer gives back what was appended, in order, across blocks
// kept in memory and blocks written to its temporary file.
#include "harness/metrics/spill_buffer.h"

#include <array>
#include <catch2/catch.hpp>
#include <cstdint>

namespace hb {
namespace {

TEST_CASE("values come back in order across memory and file blocks") {
  using Item = std::array<int64_t, 2>;
  SpillBuffer<Item> buffer;
  const std::size_t count = 3 * SpillBuffer<Item>::kBlockItems + 17;  // three blocks on disk
  for (std::size_t i = 0; i < count; ++i)
    buffer.push_back({static_cast<int64_t>(i), -static_cast<int64_t>(3 * i)});
  REQUIRE(buffer.size() == count);

  std::size_t seen = 0;
  bool in_order = true;
  buffer.for_each([&](const Item& item) {
    in_order = in_order && item[0] == static_cast<int64_t>(seen) &&
               item[1] == -static_cast<int64_t>(3 * seen);
    ++seen;
  });
  CHECK(seen == count);
  CHECK(in_order);

  // Two readers at once keep their own places.
  SpillBuffer<Item>::Reader first(buffer), second(buffer);
  Item a{}, b{};
  for (int i = 0; i < 5; ++i) REQUIRE(first.next(a));
  REQUIRE(second.next(b));
  CHECK(a[0] == 4);
  CHECK(b[0] == 0);
}

TEST_CASE("an empty or short buffer stays in memory and reads back") {
  SpillBuffer<double> buffer;
  SpillBuffer<double>::Reader empty(buffer);
  double value = 0;
  CHECK_FALSE(empty.next(value));
  buffer.push_back(2.5);
  SpillBuffer<double>::Reader reader(buffer);
  REQUIRE(reader.next(value));
  CHECK(value == 2.5);
  CHECK_FALSE(reader.next(value));
}

}  // namespace
}  // namespace hb
