// Where the learning record store (LRS) is, how to sign in, and the IRI base of the activities
// we report: read from a file and the environment, never from the training record (the secret
// would travel with every copy of it).
//
// Sources, later ones winning key by key:
//  1. a JSON file: the one given (`--config FILE`), else $ACDR_LRS_CONFIG, else
//     $XDG_CONFIG_HOME/acdr/lrs.json (default ~/.config/acdr/lrs.json) when it exists:
//       {"endpoint": "https://lrs.example.org/xapi/", "key": "...", "secret": "...",
//        "activity_iri_base": "https://training.example.org/acdr/",
//        "send_after_attempt": true, "timeout_s": 30}
//     A file that holds the secret must not be readable by group or others (like ssh keys).
//  2. the environment: ACDR_LRS_ENDPOINT, ACDR_LRS_KEY, ACDR_LRS_SECRET,
//     ACDR_XAPI_IRI_BASE, ACDR_LRS_SEND_AFTER_ATTEMPT (1/0, true/false).
#pragma once

#include <optional>
#include <string>

namespace acdr {

struct LrsConfig {
  /// The xAPI endpoint (the statements resource is endpoint + "statements"); empty: no LRS is
  /// configured, statements only wait in the outbox.
  std::string endpoint;
  std::string key;     ///< HTTP Basic user
  std::string secret;  ///< HTTP Basic password
  /// IRI base of the activities and extensions we mint; empty: the export's default (an
  /// example domain).
  std::string activity_iri_base;
  /// Send the outbox right after an attempt is stored (acdr run).
  bool send_after_attempt = false;
  double timeout_s = 30.0;  ///< per request
  /// Where the values came from ("FILE", "environment", "FILE + environment"), for messages.
  std::string source;

  bool has_endpoint() const { return !endpoint.empty(); }
};

struct LrsConfigLoad {
  LrsConfig config;
  std::string error;  ///< empty: loaded (possibly with nothing configured)
  bool ok() const { return error.empty(); }
};

/// Reads the configuration as described above. `path`: an explicit file, which must exist.
/// Errors name the file or variable, the value and what was expected.
LrsConfigLoad load_lrs_config(const std::optional<std::string>& path = std::nullopt);

/// Where a configuration file is looked for when none is given: $ACDR_LRS_CONFIG, else
/// $XDG_CONFIG_HOME/acdr/lrs.json, else ~/.config/acdr/lrs.json.
std::string default_lrs_config_path();

}  // namespace acdr
