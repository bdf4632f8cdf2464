// The LRS configuration from a file and the environment: see lrs_config.hpp.
#include "net/lrs_config.hpp"

#include <sys/stat.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>

namespace acdr {

namespace {

using Json = nlohmann::json;

std::string env(const char* name) {
  const char* value = std::getenv(name);
  return value ? std::string(value) : std::string();
}

// "http(s)://host[:port]/path/" without credentials, query or fragment; a missing final slash
// is added. Empty string when fine, else what is wrong.
std::string check_endpoint(std::string& url) {
  const bool http = url.rfind("http://", 0) == 0;
  const bool https = url.rfind("https://", 0) == 0;
  if (!http && !https) return "expected an http:// or https:// URL";
  const std::size_t host_start = url.find("://") + 3;
  const std::size_t path_start = url.find('/', host_start);
  const std::string authority = url.substr(host_start, path_start - host_start);
  if (authority.empty()) return "the URL names no host";
  if (authority.find('@') != std::string::npos) {
    return "credentials belong in key and secret, not in the URL";
  }
  if (url.find_first_of("?#") != std::string::npos) {
    return "expected the endpoint without a query or fragment";
  }
  if (url.back() != '/') url.push_back('/');
  return {};
}

std::string check_iri_base(const std::string& iri) {
  if (iri.rfind("http://", 0) != 0 && iri.rfind("https://", 0) != 0) {
    return "expected an absolute http:// or https:// IRI (a domain you control)";
  }
  if (iri.find_first_of(" \t\r\n?#") != std::string::npos) {
    return "expected an IRI without spaces, query or fragment";
  }
  return {};
}

std::optional<bool> parse_flag(const std::string& text) {
  if (text == "1" || text == "true" || text == "yes") return true;
  if (text == "0" || text == "false" || text == "no" || text.empty()) return false;
  return std::nullopt;
}

// Reads `path` into `config`; returns the error or "".
std::string read_file(const std::string& path, LrsConfig& config) {
  std::ifstream in(path);
  if (!in) return path + ": cannot read the LRS configuration file";
  std::stringstream text;
  text << in.rdbuf();
  Json json;
  try {
    json = Json::parse(text.str());
  } catch (const Json::parse_error& e) {
    return path + ": not valid JSON (" + e.what() + ")";
  }
  if (!json.is_object()) return path + ": expected a JSON object of LRS settings";
  for (auto item = json.begin(); item != json.end(); ++item) {
    const std::string key = item.key();
    const Json& value = item.value();
    const auto want_string = [&](std::string& out) -> std::string {
      if (!value.is_string())
        return path + ": \"" + key + "\" must be a string, got " + value.dump();
      out = value.get<std::string>();
      return {};
    };
    std::string problem;
    if (key == "endpoint") {
      problem = want_string(config.endpoint);
    } else if (key == "key") {
      problem = want_string(config.key);
    } else if (key == "secret") {
      problem = want_string(config.secret);
    } else if (key == "activity_iri_base") {
      problem = want_string(config.activity_iri_base);
    } else if (key == "send_after_attempt") {
      if (!value.is_boolean()) {
        problem = path + ": \"send_after_attempt\" must be true or false, got " + value.dump();
      } else {
        config.send_after_attempt = value.get<bool>();
      }
    } else if (key == "timeout_s") {
      if (!value.is_number() || value.get<double>() <= 0.0 || value.get<double>() > 600.0) {
        problem =
            path + ": \"timeout_s\" must be a number of seconds in (0, 600], got " + value.dump();
      } else {
        config.timeout_s = value.get<double>();
      }
    } else {
      problem = path + ": unknown key \"" + key +
                "\" (expected endpoint, key, secret, activity_iri_base, send_after_attempt, "
                "timeout_s)";
    }
    if (!problem.empty()) return problem;
  }
  if (json.contains("secret")) {
    struct stat st {};
    if (stat(path.c_str(), &st) == 0 && (st.st_mode & (S_IRWXG | S_IRWXO)) != 0) {
      std::ostringstream mode;
      mode << std::oct << (st.st_mode & 0777);
      return path + ": holds the LRS secret but other users may read it (mode 0" + mode.str() +
             "); run chmod 600 " + path;
    }
  }
  return {};
}

}  // namespace

std::string default_lrs_config_path() {
  if (std::string p = env("ACDR_LRS_CONFIG"); !p.empty()) return p;
  if (std::string xdg = env("XDG_CONFIG_HOME"); !xdg.empty()) return xdg + "/acdr/lrs.json";
  if (std::string home = env("HOME"); !home.empty()) return home + "/.config/acdr/lrs.json";
  return {};
}

LrsConfigLoad load_lrs_config(const std::optional<std::string>& path) {
  LrsConfigLoad load;
  LrsConfig& config = load.config;
  std::string file;
  if (path) {
    file = *path;
    if (!std::filesystem::exists(file)) {
      load.error = file + ": no such LRS configuration file";
      return load;
    }
  } else {
    file = default_lrs_config_path();
    // Named by $ACDR_LRS_CONFIG: must exist; the XDG default is optional.
    if (!file.empty() && !std::filesystem::exists(file)) {
      if (!env("ACDR_LRS_CONFIG").empty()) {
        load.error = file + " (ACDR_LRS_CONFIG): no such LRS configuration file";
        return load;
      }
      file.clear();
    }
  }
  if (!file.empty()) {
    if (std::string problem = read_file(file, config); !problem.empty()) {
      load.error = problem;
      return load;
    }
    config.source = file;
  }

  bool from_env = false;
  const auto take = [&](const char* name, std::string& out) {
    if (std::string value = env(name); !value.empty()) {
      out = value;
      from_env = true;
    }
  };
  take("ACDR_LRS_ENDPOINT", config.endpoint);
  take("ACDR_LRS_KEY", config.key);
  take("ACDR_LRS_SECRET", config.secret);
  take("ACDR_XAPI_IRI_BASE", config.activity_iri_base);
  if (const char* raw = std::getenv("ACDR_LRS_SEND_AFTER_ATTEMPT")) {
    const std::optional<bool> flag = parse_flag(raw);
    if (!flag) {
      load.error = std::string("ACDR_LRS_SEND_AFTER_ATTEMPT='") + raw +
                   "': expected 1/0, true/false or yes/no";
      return load;
    }
    config.send_after_attempt = *flag;
    from_env = true;
  }
  if (from_env)
    config.source = config.source.empty() ? "environment" : config.source + " + environment";
  const std::string where = config.source.empty() ? "LRS configuration" : config.source;

  if (!config.endpoint.empty()) {
    if (std::string problem = check_endpoint(config.endpoint); !problem.empty()) {
      load.error = where + ": endpoint '" + config.endpoint + "': " + problem;
      return load;
    }
  }
  if (config.key.empty() != config.secret.empty()) {
    load.error = where + ": give both key and secret (HTTP Basic), or neither";
    return load;
  }
  if (!config.activity_iri_base.empty()) {
    if (std::string problem = check_iri_base(config.activity_iri_base); !problem.empty()) {
      load.error = where + ": activity_iri_base '" + config.activity_iri_base + "': " + problem;
      return load;
    }
  }
  if (config.send_after_attempt && config.endpoint.empty()) {
    load.error = where + ": send_after_attempt is on but no endpoint is set";
    return load;
  }
  return load;
}

}  // namespace acdr
