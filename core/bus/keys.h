#pragma once
// CURVE keys (ZeroMQ RFC 26, CurveZMQ): a key pair is a Curve25519 public key and its secret
// key, 32 bytes each, written as 40 characters of Z85 (ZeroMQ RFC 32). enact keeps each in a
// file of its own: NAME.pub (the public key, to give to others) and NAME.key (the secret key,
// file mode 0600, never overwritten). Both are text: '#' comment lines, then the key.
#include <string>

namespace enact::bus {

struct KeyPair {
  std::string public_z85;  // 40 characters
  std::string secret_z85;  // 40 characters
};

// a fresh key pair (zmq_curve_keypair); throws std::runtime_error when libzmq has no CURVE
KeyPair new_key_pair();

// the public key of a secret key (zmq_curve_public); throws config::Error when `secret_z85`
// is not 40 characters of Z85
std::string public_of(const std::string& secret_z85);

// true when `key` is 40 characters of Z85 (any 32-byte key)
bool is_z85_key(const std::string& key);

// a short name of a public key for logs: its first 8 Z85 characters
std::string fingerprint(const std::string& public_z85);

// where `enact keys new` puts keys by default: $XDG_CONFIG_HOME/enact/keys, else
// ~/.config/enact/keys
std::string default_key_dir();

// writes DIR/NAME.key (mode 0600) and DIR/NAME.pub of a fresh key pair, creating DIR (mode
// 0700); throws config::Error when NAME is not a plain file name, a file exists already
// (a key is never overwritten) or a file cannot be written. The pair written.
KeyPair write_key_pair(const std::string& dir, const std::string& name);

// the key in a key file (comment lines skipped), checked: a .key file must hold a secret key
// no one else can read (mode 0600 or stricter); throws config::Error naming the file and the
// fix. `what` says what the file is for in messages ("--key", "server secret key").
std::string read_key_file(const std::string& path, const std::string& what);

// the public key a file gives: a .pub file's key, or the public key of a .key file's secret
std::string read_public_key(const std::string& path, const std::string& what);

}  // namespace enact::bus
