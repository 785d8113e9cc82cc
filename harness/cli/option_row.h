// A row of a command's option table (option_table.h): what it is
// (command_syntax.h) and where its values go, a member of the command's
// arguments or a member of one of its members.
#pragma once

#include <functional>
#include <optional>
#include <string>
#include <type_traits>
#include <utility>
#include <vector>

#include "harness/cli/command_syntax.h"

namespace hb {

template <class T>
struct IsVector : std::false_type {};
template <class T>
struct IsVector<std::vector<T>> : std::true_type {};
template <class T>
struct IsOptional : std::false_type {};
template <class T>
struct IsOptional<std::optional<T>> : std::true_type {};

/// Stores `value` in `field`: appended to a vector, converted to an
/// arithmetic field (or optional one), assigned otherwise.
template <class T, class V>
void store_value(T& field, const V& value) {
  if constexpr (IsVector<T>::value)
    field.emplace_back(value);
  else if constexpr (std::is_arithmetic_v<T>)
    field = static_cast<T>(value);
  else if constexpr (IsOptional<T>::value && std::is_arithmetic_v<typename T::value_type>)
    field = static_cast<typename T::value_type>(value);
  else
    field = value;
}

/// A row's target inside a member of the arguments: args.*outer.*inner.
template <class Args, class Outer, class T>
auto member_of(Outer Args::*outer, T Outer::*inner) {
  return [outer, inner](Args& args, const auto& value) { store_value(args.*outer.*inner, value); };
}

/// A row of a command's option table: what it is and where its values go.
template <class Args>
struct OptionRow {
  using Store = std::function<void(Args&, const std::vector<std::string>&)>;
  OptionSpec spec;
  Store store;
  OptionRow with_default(std::string text) && {
    spec.default_text = std::move(text);
    return std::move(*this);
  }
  OptionRow required() && {
    spec.required = true;
    return std::move(*this);
  }
  OptionRow repeatable() && {
    spec.repeatable = true;
    return std::move(*this);
  }
  OptionRow missing(std::string what) && {
    spec.missing = std::move(what);
    return std::move(*this);
  }
};

/// `first` and then `more`: a command's own rows and rows it shares.
template <class Row>
std::vector<Row> rows_then(std::vector<Row> first, std::vector<Row> more) {
  for (Row& row : more) first.push_back(std::move(row));
  return first;
}

}  // namespace hb
