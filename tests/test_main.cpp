// The main of every test executable (one per test folder). Each test case
// carries its file's name as a tag ([#mesh_ccd_test]), so that CTest lists
// and names the cases of each *_test.cpp on its own (cmake/hapticbench.cmake,
// hb_test_folder).
#define CATCH_CONFIG_RUNNER
#include <catch2/catch.hpp>

int main(int argc, char* argv[]) {
  Catch::Session session;
  session.configData().filenamesAsTags = true;
  const int parse_error = session.applyCommandLine(argc, argv);
  if (parse_error != 0) return parse_error;
  return session.run();
}
