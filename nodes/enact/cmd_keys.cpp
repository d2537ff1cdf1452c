// enact keys new NAME | show FILE: the CURVE keys of graphs and their clients.
#include <cstdio>

#include "core/bus/keys.h"
#include "nodes/enact/commands.h"

namespace enact::cli {
namespace {

constexpr const char* kKeysHelp = R"(usage: enact keys new NAME [--dir DIR]
       enact keys show FILE

Keys for remote access (docs/remote-access.md): a graph launched with --access lets in
only the clients its access file lists, each by its public key, over encrypted connections
(ZeroMQ CURVE).
  new    make a key pair: DIR/NAME.key, the secret key (file mode 0600: keep it on this
         machine, never share it) and DIR/NAME.pub, the public key (give it to whoever must
         know it). An existing key is never overwritten. Prints the public key.
  show   print the public key of FILE (a .pub file, or a .key file's public key)

options:
  --dir DIR   where new keys go (default $XDG_CONFIG_HOME/enact/keys, else ~/.config/enact/keys)
)";

}  // namespace

int keys(int argc, char** argv) {
  const Args a = parse(argc, argv, 2, {"dir"}, {});
  if (a.flag("help") || a.positional.empty()) {
    std::fputs(kKeysHelp, a.flag("help") ? stdout : stderr);
    return a.flag("help") ? 0 : 2;
  }
  const std::string& verb = a.positional[0];
  if (a.has("dir") && verb != "new") throw UsageError("--dir is for `enact keys new`");
  if (verb == "new" && a.positional.size() == 2) {
    const std::string dir = a.get("dir", bus::default_key_dir());
    const bus::KeyPair pair = bus::write_key_pair(dir, a.positional[1]);
    std::printf("secret key %s/%s.key (keep it here)\npublic key %s/%s.pub: %s\n", dir.c_str(), a.positional[1].c_str(), dir.c_str(), a.positional[1].c_str(), pair.public_z85.c_str());
    return 0;
  }
  if (verb == "show" && a.positional.size() == 2) {
    std::printf("%s\n", bus::read_public_key(a.positional[1], "key").c_str());
    return 0;
  }
  throw UsageError("use: enact keys new NAME [--dir DIR] | enact keys show FILE");
}

}  // namespace enact::cli
