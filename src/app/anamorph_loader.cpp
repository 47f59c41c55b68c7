// anamorph-loader: reads a model with assimp in a process of its own and hands it back to the
// anamorph process that started it (scene/isolated.h says why a program rather than a fork).
// Started by run_helper, never by users: its arguments are run_helper's, then `assimp FILE`, and
// `--beneath FOLDER` when the reads must stay in that folder (the editor's, whose descriptor the
// parent hands over as kHelperFolderFd: io/read_file.h, ReadConfinement).
#include <cstdio>
#include <memory>
#include <string>

#include "io/confined_folder.h"
#include "io/read_file.h"
#include "scene/assimp_child.h"
#include "scene/isolated.h"

int main(int argc, char** argv) {
  anamorph::HelperCall call;
  const bool ok = anamorph::parse_helper_args(argc, argv, &call) &&
                  (call.args.size() == 2 || (call.args.size() == 4 && call.args[2] == "--beneath"));
  if (!ok || call.args[0] != "assimp") {
    std::fputs(
        "anamorph-loader: anamorph starts this program to read models with assimp; it is not a "
        "command of its own\n",
        stderr);
    return 2;
  }
  std::unique_ptr<anamorph::ConfinedFolder> folder;
  if (call.args.size() == 4)
    folder = std::make_unique<anamorph::ConfinedFolder>(anamorph::kHelperFolderFd, call.args[3]);
  const anamorph::ScopedReadConfinement confined({folder.get(), nullptr, nullptr});
  anamorph::serve_isolated(call, [&] { return anamorph::assimp_answer(call.args[1]); });
}
