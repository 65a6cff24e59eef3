// A stand-in for the hexdem program with only the `post` subcommand, for the tests of
// `hexdem post`: the same parsing, error handling and exit codes as solver/app/hexdem_main.cpp.
#include <CLI/CLI.hpp>

#include <exception>
#include <iostream>

#include "hexdem/error.hpp"
#include "hexdem/post/post_command.hpp"

int main(int argc, char** argv) {
  CLI::App app{"hexdem: discrete element lattices for impact and fracture", "hexdem"};
  app.require_subcommand(1);
  hexdem::post::PostCommand post = hexdem::post::add_post_command(app);
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    const int code = app.exit(e);
    return code == 0 ? hexdem::kExitOk : hexdem::kExitInputError;
  }
  try {
    if (*post.cmd) return post.run();
  } catch (const hexdem::InputError& e) {
    std::cerr << "hexdem: error: " << e.what() << "\n";
    return hexdem::kExitInputError;
  } catch (const std::exception& e) {
    std::cerr << "hexdem: internal error: " << e.what() << "\n";
    return hexdem::kExitFailure;
  }
  return hexdem::kExitOk;
}
