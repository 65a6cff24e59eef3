#pragma once
/// \file post_command.hpp
/// The `post` subcommand of the hexdem program:
///
///     hexdem post {maxshear,cracks,fragments} SERIES.pvd|FRAME.vtu [--time T|--all] [-o OUT]
///
/// Usage in main():
///
///     CLI::App app{...};
///     hexdem::post::PostCommand post = hexdem::post::add_post_command(app);
///     app.parse(argc, argv);
///     if (*post.cmd) return post.run();   // inside the try that catches hexdem::InputError
///
/// `run` throws hexdem::InputError (one line naming the file or option and the value) on
/// bad input and returns the exit code (0) otherwise. The options are owned by `run`, which
/// must be kept alive until after parsing (CLI11 writes into them).

#include <functional>

namespace CLI {
class App;
}

namespace hexdem::post {

struct PostCommand {
  CLI::App* cmd;             ///< the `post` subcommand (owned by the parent app)
  std::function<int()> run;  ///< runs the parsed command
};

/// Adds `post` and its three subcommands to `app`.
PostCommand add_post_command(CLI::App& app);

}  // namespace hexdem::post
