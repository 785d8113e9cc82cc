// A command's arguments as one table: each row is an option or a positional
// argument, with what --help and the command reference (docs/command-line.md)
// say of it and where its value goes. Parsing, the --help text and the
// Markdown reference all come from the rows, so they cannot disagree (as
// Google Benchmark's flags and Catch2's Clara parsers do).
//
//   using Table = OptionTable<CompareArguments>;
//   static const Table table({"compare", {"what it does"}},
//       {Table::positional("BASELINE", "a run folder", 1, 1, &CompareArguments::baseline),
//        Table::flag("--gate", "exit 1 on a regression", &CompareArguments::gate),
//        Table::number("--alpha", "X", "significance level", probability(),
//                      member_of(&CompareArguments::options, &CompareOptions::alpha))
//            .with_default("0.01")});
//   const CompareArguments parsed = table.parse(args);  // throws UsageError, HelpRequested
#pragma once

#include <cstddef>
#include <functional>
#include <string>
#include <type_traits>
#include <utility>
#include <vector>

#include "harness/cli/command_line.h"
#include "harness/cli/command_syntax.h"
#include "harness/cli/option_row.h"
#include "harness/progress/progress_display.h"

namespace hb {

template <class Args>
class OptionTable {
 public:
  using Store = typename OptionRow<Args>::Store;

  using Row = OptionRow<Args>;

  OptionTable(CommandText text, std::vector<Row> rows) : syntax_{std::move(text), {}} {
    for (Row& row : rows) {
      syntax_.rows.push_back(std::move(row.spec));
      stores_.push_back(std::move(row.store));
    }
  }

  /// The arguments `args` give, from default-made ones; throws UsageError
  /// or HelpRequested.
  Args parse(const std::vector<std::string>& args) const {
    Args parsed{};
    parse_by_rows(syntax_.rows, args, [&](std::size_t row, const std::vector<std::string>& values) {
      stores_[row](parsed, values);
    });
    return parsed;
  }

  const CommandSyntax& syntax() const { return syntax_; }
  std::string usage() const { return usage_text(syntax_); }

  /// A flag; `target`: a bool member (set), or a callable (Args&).
  template <class Target>
  static Row flag(std::string name, std::string help, Target target) {
    return {spec(std::move(name), "", std::move(help)),
            [target](Args& args, const std::vector<std::string>&) {
              if constexpr (!std::is_member_object_pointer_v<Target> &&
                            std::is_invocable_v<Target, Args&>)
                target(args);
              else
                setter<bool>(target)(args, true);
            }};
  }

  /// An option with a text value; `target`: a member (a vector: repeatable,
  /// each value appended), or a callable (Args&, const std::string&) that
  /// may throw UsageError.
  template <class Target>
  static Row value(std::string name, std::string value_name, std::string help, Target target) {
    Row row{spec(std::move(name), std::move(value_name), std::move(help)), {}};
    row.spec.repeatable = appends<Target>();
    row.store = [set = setter<std::string>(target)](Args& args,
                                                    const std::vector<std::string>& values) {
      set(args, values.front());
    };
    return row;
  }

  /// An option with several values ("--range LO HI"); `target`: a callable
  /// (Args&, const std::vector<std::string>&).
  static Row values(std::string name, std::string value_names, std::string help, Store target) {
    return {spec(std::move(name), std::move(value_names), std::move(help)), std::move(target)};
  }

  /// A number in `range`; `target`: a member or a callable (Args&, double).
  template <class Target>
  static Row number(std::string name, std::string value_name, std::string help, NumberRange range,
                    Target target) {
    return checked<double>(std::move(name), std::move(value_name), std::move(help), target,
                           [range](const std::string& option, const std::string& text) {
                             return number_in(option, text, range);
                           });
  }

  /// A whole number in `range`; `target`: a member or a callable (Args&, long long).
  template <class Target>
  static Row whole(std::string name, std::string value_name, std::string help, WholeRange range,
                   Target target) {
    return checked<long long>(std::move(name), std::move(value_name), std::move(help), target,
                              [range](const std::string& option, const std::string& text) {
                                return whole_number_in(option, text, range);
                              });
  }

  /// Positional values, between `min` and `max` of them (kAnyCount: no
  /// limit); `target`: a member (a vector for several) or a callable
  /// (Args&, const std::string&).
  template <class Target>
  static Row positional(std::string name, std::string help, std::size_t min, std::size_t max,
                        Target target) {
    Row row = value(std::move(name), "", std::move(help), target);
    row.spec.positional = true;
    row.spec.repeatable = false;
    row.spec.min_count = min;
    row.spec.max_count = max;
    return row;
  }

  /// --progress STYLE; `target`: a std::optional<ProgressStyle> member or a
  /// callable (Args&, ProgressStyle).
  template <class Target>
  static Row progress(Target target) {
    return {
        spec("--progress", "STYLE",
             "how progress shows on stderr: bar (a live line; the default on a terminal), "
             "plain (a line per phase; the default otherwise) or none"),
        [set = setter<ProgressStyle>(target)](Args& args, const std::vector<std::string>& values) {
          set(args, progress_style_in(values.front()));
        }};
  }
  /// --quiet, as --progress none.
  template <class Target>
  static Row quiet(Target target) {
    return {spec("--quiet", "", "no progress, as --progress none"),
            [set = setter<ProgressStyle>(target)](Args& args, const std::vector<std::string>&) {
              set(args, ProgressStyle::kNone);
            }};
  }

 private:
  static OptionSpec spec(std::string name, std::string value_name, std::string help) {
    OptionSpec made;
    made.name = std::move(name);
    made.value_name = std::move(value_name);
    made.help = std::move(help);
    return made;
  }

  // A row whose value `read` turns into a V (or throws UsageError) for `target`.
  template <class V, class Target, class Read>
  static Row checked(std::string name, std::string value_name, std::string help, Target target,
                     Read read) {
    const std::string option = name;
    return {spec(std::move(name), std::move(value_name), std::move(help)),
            [option, read, set = setter<V>(target)](Args& args,
                                                    const std::vector<std::string>& values) {
              set(args, read(option, values.front()));
            }};
  }

  template <class Target>
  static constexpr bool appends() {
    if constexpr (std::is_member_object_pointer_v<Target>)
      return IsVector<
          std::remove_reference_t<decltype(std::declval<Args&>().*std::declval<Target>())>>::value;
    else
      return false;
  }

  // A callable (Args&, const V&) storing into `target`: a member, or the
  // callable itself.
  template <class V, class Target>
  static std::function<void(Args&, const V&)> setter(Target target) {
    if constexpr (std::is_member_object_pointer_v<Target>)
      return [target](Args& args, const V& value) { store_value(args.*target, value); };
    else
      return target;
  }

  CommandSyntax syntax_;
  std::vector<Store> stores_;
};

}  // namespace hb
