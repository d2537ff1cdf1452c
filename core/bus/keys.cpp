#include "core/bus/keys.h"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <stdexcept>

#include <zmq.h>

#include "core/config/yaml.h"

namespace enact::bus {
namespace {

constexpr std::size_t kZ85KeyChars = 40;

// true when `path` names a secret key file
bool is_secret_file(const std::string& path) { return std::filesystem::path(path).extension() == ".key"; }

[[noreturn]] void refuse_existing(const std::string& path) {
  throw config::Error(path + ": exists already, and a key is never overwritten\n  fix: choose another NAME, or remove the old key first");
}

// writes `text` to a new file `path` with `mode`; refuses an existing file (O_EXCL)
void write_new_file(const std::string& path, const std::string& text, mode_t mode) {
  const int fd = ::open(path.c_str(), O_WRONLY | O_CREAT | O_EXCL, mode);
  if (fd < 0) {
    if (errno == EEXIST) refuse_existing(path);
    throw config::Error(path + ": cannot create: " + std::strerror(errno) + "\n  fix: give a --dir you can write to");
  }
  // the umask may have taken bits away, never added any: set exactly `mode`
  const bool ok = ::fchmod(fd, mode) == 0 && ::write(fd, text.data(), text.size()) == static_cast<ssize_t>(text.size());
  ::close(fd);
  if (!ok) throw config::Error(path + ": cannot write the key\n  fix: check the disk and the folder's permissions");
}

}  // namespace

KeyPair new_key_pair() {
  if (!zmq_has("curve")) throw std::runtime_error("this libzmq has no CURVE security (built without libsodium)");
  char pub[kZ85KeyChars + 1] = {};
  char sec[kZ85KeyChars + 1] = {};
  if (zmq_curve_keypair(pub, sec) != 0) throw std::runtime_error(std::string("zmq_curve_keypair failed: ") + zmq_strerror(zmq_errno()));
  return {pub, sec};
}

bool is_z85_key(const std::string& key) {
  // Z85 (RFC 32): 40 characters from its 85-character alphabet decode to 32 bytes
  std::uint8_t bytes[32];
  return key.size() == kZ85KeyChars && zmq_z85_decode(bytes, key.c_str()) != nullptr;
}

std::string public_of(const std::string& secret_z85) {
  if (!is_z85_key(secret_z85)) throw config::Error("not a secret key (40 characters of Z85)\n  fix: make one with `enact keys new NAME`");
  char pub[kZ85KeyChars + 1] = {};
  if (zmq_curve_public(pub, secret_z85.c_str()) != 0) throw std::runtime_error(std::string("zmq_curve_public failed: ") + zmq_strerror(zmq_errno()));
  return pub;
}

std::string fingerprint(const std::string& public_z85) { return public_z85.substr(0, 8); }

std::string default_key_dir() {
  const char* xdg = std::getenv("XDG_CONFIG_HOME");
  if (xdg && *xdg) return std::string(xdg) + "/enact/keys";
  const char* home = std::getenv("HOME");
  return std::string(home && *home ? home : ".") + "/.config/enact/keys";
}

KeyPair write_key_pair(const std::string& dir, const std::string& name) {
  if (name.empty() || name.find('/') != std::string::npos || name.front() == '.') {
    throw config::Error("key name '" + name + "': not a plain file name\n  fix: give a name like lab-pc (letters, digits, - and _)");
  }
  std::error_code ec;
  std::filesystem::create_directories(dir, ec);
  if (ec) throw config::Error(dir + ": cannot create the key folder: " + ec.message() + "\n  fix: give a --dir you can write to");
  ::chmod(dir.c_str(), 0700);
  const std::string secret_path = dir + "/" + name + ".key";
  const std::string public_path = dir + "/" + name + ".pub";
  // refuse before writing anything when either exists
  for (const std::string& p : {secret_path, public_path}) {
    if (std::filesystem::exists(p)) refuse_existing(p);
  }
  const KeyPair pair = new_key_pair();
  write_new_file(secret_path, "# enact secret key '" + name + "': keep it on this machine, never share it\n" + pair.secret_z85 + "\n", 0600);
  write_new_file(public_path, "# enact public key '" + name + "': give it to the graphs and clients that must know it\n" + pair.public_z85 + "\n", 0644);
  return pair;
}

std::string read_key_file(const std::string& path, const std::string& what) {
  std::ifstream in(path);
  if (!in) throw config::Error(path + ": cannot read the " + what + " file\n  fix: give the path of a key made by `enact keys new NAME`");
  if (is_secret_file(path)) {
    struct stat st{};
    if (::stat(path.c_str(), &st) == 0 && (st.st_mode & 077) != 0) {
      throw config::Error(path + ": a secret key others can read (mode " + std::to_string((st.st_mode >> 6) & 7) + std::to_string((st.st_mode >> 3) & 7) +
                          std::to_string(st.st_mode & 7) + ")\n  fix: chmod 600 " + path + ", and make a new key if others may have read it");
    }
  }
  std::string line;
  int number = 0;
  while (std::getline(in, line)) {
    ++number;
    while (!line.empty() && (line.back() == '\r' || line.back() == ' ')) line.pop_back();
    if (line.empty() || line.front() == '#') continue;
    if (!is_z85_key(line)) {
      throw config::Error(path + ":" + std::to_string(number) + ": not a key (40 characters of Z85)\n  fix: give a file made by `enact keys new NAME`");
    }
    return line;
  }
  throw config::Error(path + ": holds no key\n  fix: give a file made by `enact keys new NAME`");
}

std::string read_public_key(const std::string& path, const std::string& what) {
  const std::string key = read_key_file(path, what);
  return is_secret_file(path) ? public_of(key) : key;
}

}  // namespace enact::bus
