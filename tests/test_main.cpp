// The main of every test executable (one per test folder). Each test case
// carries its file's name as a tag ([#mesh_ccd_test]), so that a case can be
// selected with its file's other cases ("[#mesh_ccd_test]").
//
// `--list-tests-by-file` prints one line per test case, "<file stem>\t<name>",
// in declaration order: cmake/discover_folder_tests.cmake registers every
// case with CTest under its own file's name ("algorithms/ccd/mesh_ccd_test:
// <case>") from this one listing of the executable.
#define CATCH_CONFIG_RUNNER
#include <catch2/catch.hpp>
#include <iostream>
#include <string>
#include <string_view>

namespace {
// "tests/algorithms/ccd/mesh_ccd_test.cpp" -> "mesh_ccd_test".
std::string file_stem(const std::string& path) {
  const std::size_t slash = path.find_last_of("\\/");
  std::string stem = slash == std::string::npos ? path : path.substr(slash + 1);
  const std::size_t dot = stem.find_last_of('.');
  if (dot != std::string::npos) stem.erase(dot);
  return stem;
}
}  // namespace

int main(int argc, char* argv[]) {
  Catch::Session session;
  session.configData().filenamesAsTags = true;
  if (argc == 2 && std::string_view(argv[1]) == "--list-tests-by-file") {
    for (const Catch::TestCase& test : Catch::getAllTestCasesSorted(session.config()))
      std::cout << file_stem(test.lineInfo.file) << '\t' << test.name << '\n';
    return 0;
  }
  const int parse_error = session.applyCommandLine(argc, argv);
  if (parse_error != 0) return parse_error;
  return session.run();
}
