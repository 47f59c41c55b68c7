// anamorph-loader: reads a model with assimp in a process of its own and hands it back to the
// anamorph process that started it (scene/isolated.h says why a program rather than a fork).
// Started by run_helper, never by users: its arguments are run_helper's, then `assimp FILE`.
#include <cstdio>
#include <string>

#include "scene/assimp_child.h"
#include "scene/isolated.h"

int main(int argc, char** argv) {
  anamorph::HelperCall call;
  if (!anamorph::parse_helper_args(argc, argv, &call) || call.args.size() != 2 ||
      call.args[0] != "assimp") {
    std::fputs(
        "anamorph-loader: anamorph starts this program to read models with assimp; it is not a "
        "command of its own\n",
        stderr);
    return 2;
  }
  anamorph::serve_isolated(call, [&] { return anamorph::assimp_answer(call.args[1]); });
}
