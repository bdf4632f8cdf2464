// Typed reads with errors that say where (line, JSON path), what was found and what was
// expected. Values are converted to SI here, once.
#include "scenarios/object_reader.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <regex>

#include "scenarios/key_suggestion.hpp"

namespace acdr {

using nlohmann::json;

// ---------------------------------------------------------------------------------------------
// LoadContext

void LoadContext::error(const std::string& pointer, std::string message) {
  error_located(pointer, pointer, std::move(message));
}

void LoadContext::error_located(const std::string& pointer, const std::string& located_at,
                                std::string message) {
  if (truncated_) return;
  const TextPosition where = index_.find(located_at);
  if (errors_.size() >= kMaxErrors) {
    truncated_ = true;
    errors_.push_back({file_, where.line, where.column, "",
                       "too many errors; the first " + std::to_string(kMaxErrors) +
                           " are shown, the rest were not reported"});
    return;
  }
  errors_.push_back({file_, where.line, where.column, pointer, std::move(message)});
}

// ---------------------------------------------------------------------------------------------
// Formatting

std::string format_number(double x) {
  char buf[64];
  std::snprintf(buf, sizeof buf, "%.9g", x);
  return buf;
}

std::string describe_value(const json& value) {
  switch (value.type()) {
    case json::value_t::null: return "null";
    case json::value_t::boolean: return value.get<bool>() ? "true" : "false";
    case json::value_t::number_integer: return std::to_string(value.get<std::int64_t>());
    case json::value_t::number_unsigned: return std::to_string(value.get<std::uint64_t>());
    case json::value_t::number_float: return format_number(value.get<double>());
    case json::value_t::string: {
      // Quoted and shortened; dump() escapes, and `replace` keeps a cut UTF-8 sequence harmless.
      const std::string& s = value.get_ref<const std::string&>();
      constexpr std::size_t kShown = 40;
      const bool cut = s.size() > kShown;
      const std::string shown = json(s.substr(0, kShown)).dump(-1, ' ', false, json::error_handler_t::replace);
      return "string " + (cut ? shown.substr(0, shown.size() - 1) + "...\"" : shown);
    }
    case json::value_t::array:
      return "an array of " + std::to_string(value.size()) + (value.size() == 1 ? " item" : " items");
    case json::value_t::object:
      return "an object with " + std::to_string(value.size()) + (value.size() == 1 ? " key" : " keys");
    default: return "an unsupported value";
  }
}

namespace {

std::string in_quotes(const std::string& s) { return "\"" + s + "\""; }

std::string with_unit(double x, const char* symbol) {
  std::string out = format_number(x);
  if (symbol != nullptr && symbol[0] != '\0') {
    out += ' ';
    out += symbol;
  }
  return out;
}

std::string range_text(const Range& r, double to_si, const char* symbol) {
  std::string out;
  if (r.min) out += (r.min_exclusive ? "> " : ">= ") + with_unit(*r.min / to_si, symbol);
  if (r.max) {
    if (!out.empty()) out += " and ";
    out += (r.max_exclusive ? "< " : "<= ") + with_unit(*r.max / to_si, symbol);
  }
  return out.empty() ? "a finite number" : out;
}

/// Range violation test in SI, with a relative tolerance for inclusive bounds so that a value
/// written exactly at a bound in another unit (10 mm against 0.01 m) is not rejected by
/// rounding of the conversion.
bool inside(const Range& r, double v) {
  constexpr double kTol = 1e-12;
  if (!std::isfinite(v)) return false;
  if (r.min) {
    const double m = *r.min;
    if (r.min_exclusive ? !(v > m) : v < m - kTol * std::fabs(m)) return false;
  }
  if (r.max) {
    const double m = *r.max;
    if (r.max_exclusive ? !(v < m) : v > m + kTol * std::fabs(m)) return false;
  }
  return true;
}

/// A denormal (subnormal) number: non-zero but below the smallest normal double. Never a
/// physical value; arithmetic on it is slow and loses precision.
bool denormal(double v) { return std::fpclassify(v) == FP_SUBNORMAL; }

std::string denormal_text(double shown, const char* symbol, const std::string& expected) {
  return "out of range (got " + with_unit(shown, symbol) +
         ", a denormal number, expected 0 or a normal number: " + expected + ")";
}

void set_bounds(KeyInfo& info, const Range& r, double to_si) {
  if (r.min) (r.min_exclusive ? info.exclusive_minimum : info.minimum) = *r.min / to_si;
  if (r.max) (r.max_exclusive ? info.exclusive_maximum : info.maximum) = *r.max / to_si;
}

KeyInfo key_info(std::string pattern, std::string type, bool required, bool group_required = false) {
  KeyInfo info;
  info.pattern = std::move(pattern);
  info.type = std::move(type);
  info.required = required;
  info.group_required = group_required;
  return info;
}

bool is_number(const json& v) { return v.is_number(); }

/// 1 and 1.0 are both integers (JSON Schema's view); 1.5 and 1e300 are not ints.
std::optional<int> as_int(const json& v) {
  if (v.is_number_integer()) {
    if (v.is_number_unsigned()) {
      const auto u = v.get<std::uint64_t>();
      if (u > 2147483647u) return std::nullopt;
      return static_cast<int>(u);
    }
    const auto i = v.get<std::int64_t>();
    if (i < -2147483647 - 1 || i > 2147483647) return std::nullopt;
    return static_cast<int>(i);
  }
  if (v.is_number_float()) {
    const double d = v.get<double>();
    if (std::isfinite(d) && std::floor(d) == d && std::fabs(d) <= 2147483647.0) {
      return static_cast<int>(d);
    }
  }
  return std::nullopt;
}

}  // namespace

// ---------------------------------------------------------------------------------------------
// ObjectReader

ObjectReader::ObjectReader(LoadContext& ctx, const json& value, std::string pointer,
                           std::string pattern)
    : ctx_(&ctx), pointer_(std::move(pointer)), pattern_(std::move(pattern)) {
  if (value.is_object()) {
    object_ = &value;
  } else {
    ctx.error(pointer_, "wrong type (got " + describe_value(value) + ", expected an object)");
  }
}

std::string ObjectReader::child(const std::string& key) const {
  return pointer_ + "/" + escape_pointer_token(key);
}

std::string ObjectReader::child_pattern(const std::string& key) const {
  return pattern_ + "/" + escape_pointer_token(key);
}

bool ObjectReader::has(const std::string& key) const {
  return object_ != nullptr && object_->contains(key);
}

void ObjectReader::remember(const std::string& key) {
  if (std::find(asked_.begin(), asked_.end(), key) == asked_.end()) asked_.push_back(key);
}

const json* ObjectReader::lookup(const std::string& key, Need need, const std::string& expected) {
  remember(key);
  if (object_ == nullptr) return nullptr;
  auto it = object_->find(key);
  if (it == object_->end()) {
    if (need != Need::kOptional) {
      ctx_->error_located(child(key), pointer_, "missing required key (expected " + expected + ")");
    }
    return nullptr;
  }
  return &*it;
}

bool ObjectReader::check_range(const std::string& key, double value_in_si, double shown_value,
                               const Range& si_range, double to_si, const char* symbol) {
  if (denormal(shown_value) || denormal(value_in_si)) {
    ctx_->error(child(key), denormal_text(shown_value, symbol, range_text(si_range, to_si, symbol)));
    return false;
  }
  if (inside(si_range, value_in_si)) return true;
  ctx_->error(child(key), "out of range (got " + with_unit(shown_value, symbol) + ", expected " +
                              range_text(si_range, to_si, symbol) + ")");
  return false;
}

std::optional<double> ObjectReader::number(const std::string& key, Need need, const Range& range,
                                           const char* unit_symbol) {
  KeyInfo info = key_info(child_pattern(key), "number", need == Need::kRequired);
  set_bounds(info, range, 1.0);
  ctx_->record(info);
  const std::string expected = std::string("a number") +
                               (unit_symbol[0] != '\0' ? std::string(" in ") + unit_symbol : "");
  const json* v = lookup(key, need, expected);
  if (v == nullptr) return std::nullopt;
  if (!is_number(*v)) {
    ctx_->error(child(key), "wrong type (got " + describe_value(*v) + ", expected " + expected + ")");
    return std::nullopt;
  }
  const double x = v->get<double>();
  if (!check_range(key, x, x, range, 1.0, unit_symbol)) return std::nullopt;
  return x;
}

std::optional<int> ObjectReader::integer(const std::string& key, Need need, const Range& range,
                                         const std::string& hint) {
  KeyInfo info = key_info(child_pattern(key), "integer", need == Need::kRequired);
  set_bounds(info, range, 1.0);
  ctx_->record(info);
  const json* v = lookup(key, need, hint.empty() ? "an integer" : "an integer: " + hint);
  if (v == nullptr) return std::nullopt;
  const std::optional<int> i = as_int(*v);
  if (!i) {
    ctx_->error(child(key), "wrong type (got " + describe_value(*v) + ", expected an integer)");
    return std::nullopt;
  }
  if (!check_range(key, *i, *i, range, 1.0, "")) return std::nullopt;
  return i;
}

// Records every spelling of one quantity (a key per unit) for the schema and finds the one the
// object uses. False when there is nothing to read: the object is absent, the key is missing
// (reported when required), or two spellings are given at once (reported).
bool ObjectReader::pick_spelling(const std::vector<UnitKey>& spellings, Need need,
                                 const char* json_type, int items, const Range& si_range,
                                 const std::string& expected, const UnitKey** chosen,
                                 const json** value) {
  std::vector<std::string> names;
  for (const UnitKey& u : spellings) names.push_back(u.key);
  groups_.push_back(names);
  *chosen = nullptr;
  *value = nullptr;
  for (const UnitKey& u : spellings) {
    KeyInfo info = key_info(child_pattern(u.key), json_type, false,
                            need == Need::kRequired && names.size() > 1);
    if (names.size() == 1) info.required = need == Need::kRequired;
    if (items > 0) info.min_items = info.max_items = items;
    set_bounds(info, si_range, u.to_si);
    for (const std::string& other : names) {
      if (other != u.key) info.alternatives.push_back(other);
    }
    ctx_->record(info);
    remember(u.key);
    if (object_ != nullptr && object_->contains(u.key)) {
      if (*chosen != nullptr) {
        ctx_->error(child(u.key), "give either " + in_quotes((*chosen)->key) + " or " +
                                      in_quotes(u.key) +
                                      ", not both (they are the same quantity in different units)");
        return false;
      }
      *chosen = &u;
      *value = &object_->at(u.key);
    }
  }
  if (object_ == nullptr) return false;
  if (*chosen == nullptr) {
    if (need != Need::kOptional) {
      ctx_->error_located(child(names.front()), pointer_,
                          "missing required key (expected " + expected + ")");
    }
    return false;
  }
  return true;
}

std::optional<double> ObjectReader::quantity(const std::vector<UnitKey>& spellings, Need need,
                                             const Range& si_range) {
  std::vector<std::string> names;
  for (const UnitKey& u : spellings) names.push_back(u.key);
  std::string expected = "a number";
  for (std::size_t i = 0; i < names.size(); ++i) {
    const UnitKey& u = spellings[i];
    expected += (i == 0 ? " in " : i + 1 == names.size() ? ", or in " : ", in ");
    expected += std::string(u.symbol) + " as " + in_quotes(u.key);
  }
  const UnitKey* chosen = nullptr;
  const json* value = nullptr;
  if (!pick_spelling(spellings, need, "number", 0, si_range, expected, &chosen, &value))
    return std::nullopt;
  if (!is_number(*value)) {
    ctx_->error(child(chosen->key), "wrong type (got " + describe_value(*value) + ", expected a number in " +
                                        chosen->symbol + ")");
    return std::nullopt;
  }
  const double shown = value->get<double>();
  const double si = shown * chosen->to_si;
  if (!check_range(chosen->key, si, shown, si_range, chosen->to_si, chosen->symbol)) return std::nullopt;
  return si;
}

std::optional<Vec3> ObjectReader::vector3(const std::vector<UnitKey>& spellings, Need need,
                                          const Range& si_range) {
  std::vector<std::string> names;
  for (const UnitKey& u : spellings) names.push_back(u.key);
  std::string expected = "[x, y, z]";
  for (std::size_t i = 0; i < names.size(); ++i) {
    const UnitKey& u = spellings[i];
    expected += (i == 0 ? " in " : ", or in ");
    expected += std::string(u.symbol[0] != '\0' ? u.symbol : "no unit") + " as " + in_quotes(u.key);
  }
  const UnitKey* chosen = nullptr;
  const json* value = nullptr;
  if (!pick_spelling(spellings, need, "array", 3, si_range, expected, &chosen, &value))
    return std::nullopt;
  const std::string key = chosen->key;
  const std::string unit_phrase =
      chosen->symbol[0] != '\0' ? std::string(" in ") + chosen->symbol : std::string();
  if (!value->is_array() || value->size() != 3) {
    ctx_->error(child(key), "wrong type (got " + describe_value(*value) +
                                ", expected an array of 3 numbers [x, y, z]" + unit_phrase + ")");
    return std::nullopt;
  }
  Vec3 out;
  bool ok = true;
  for (int i = 0; i < 3; ++i) {
    const json& c = (*value)[static_cast<std::size_t>(i)];
    const std::string item = child(key) + "/" + std::to_string(i);
    if (!is_number(c)) {
      ctx_->error(item, "wrong type (got " + describe_value(c) + ", expected a number" + unit_phrase + ")");
      ok = false;
      continue;
    }
    const double shown = c.get<double>();
    out[i] = shown * chosen->to_si;
    if (denormal(shown) || denormal(out[i])) {
      ctx_->error(item, denormal_text(shown, chosen->symbol, range_text(si_range, chosen->to_si, chosen->symbol)));
      ok = false;
    } else if (!inside(si_range, out[i])) {
      ctx_->error(item, "out of range (got " + with_unit(shown, chosen->symbol) + ", expected " +
                            range_text(si_range, chosen->to_si, chosen->symbol) + ")");
      ok = false;
    }
  }
  if (!ok) return std::nullopt;
  return out;
}

std::optional<std::vector<double>> ObjectReader::numbers(const std::string& key, Need need,
                                                         std::size_t count) {
  KeyInfo info = key_info(child_pattern(key), "array", need == Need::kRequired);
  info.min_items = info.max_items = count;
  ctx_->record(info);
  const std::string expected = "an array of " + std::to_string(count) + " numbers";
  const json* v = lookup(key, need, expected);
  if (v == nullptr) return std::nullopt;
  if (!v->is_array() || v->size() != count) {
    ctx_->error(child(key), "wrong type (got " + describe_value(*v) + ", expected " + expected + ")");
    return std::nullopt;
  }
  std::vector<double> out;
  bool ok = true;
  for (std::size_t i = 0; i < count; ++i) {
    const json& c = (*v)[i];
    if (!is_number(c)) {
      ctx_->error(child(key) + "/" + std::to_string(i),
                  "wrong type (got " + describe_value(c) + ", expected a number)");
      ok = false;
    } else if (denormal(c.get<double>())) {
      ctx_->error(child(key) + "/" + std::to_string(i),
                  denormal_text(c.get<double>(), "", "a finite number"));
      ok = false;
    } else {
      out.push_back(c.get<double>());
    }
  }
  if (!ok) return std::nullopt;
  return out;
}

std::optional<std::string> ObjectReader::string(const std::string& key, Need need, bool nonempty,
                                                const std::vector<std::string>& allowed,
                                                const std::string& hint,
                                                const std::string& value_pattern) {
  KeyInfo info = key_info(child_pattern(key), "string", need == Need::kRequired);
  info.enum_values = allowed;
  info.value_pattern = value_pattern;
  ctx_->record(info);
  std::string expected = "a string";
  if (!allowed.empty()) {
    expected = "one of";
    for (std::size_t i = 0; i < allowed.size(); ++i) {
      expected += (i == 0 ? " " : ", ") + in_quotes(allowed[i]);
    }
    if (!value_pattern.empty()) expected += ", or text matching " + value_pattern;
  }
  const json* v = lookup(key, need, hint.empty() ? expected : expected + ": " + hint);
  if (v == nullptr) return std::nullopt;
  if (!v->is_string()) {
    ctx_->error(child(key), "wrong type (got " + describe_value(*v) + ", expected " + expected + ")");
    return std::nullopt;
  }
  const std::string& s = v->get_ref<const std::string&>();
  if (nonempty && s.find_first_not_of(" \t\r\n") == std::string::npos) {
    ctx_->error(child(key), "empty text (got " + describe_value(*v) + ", expected a non-empty string)");
    return std::nullopt;
  }
  const auto matches_pattern = [&] {
    return !value_pattern.empty() &&
           std::regex_match(s, std::regex(value_pattern, std::regex::ECMAScript));
  };
  if (!allowed.empty() && std::find(allowed.begin(), allowed.end(), s) == allowed.end() &&
      !matches_pattern()) {
    std::string message = "unknown value (got " + describe_value(*v) + ", expected " + expected + ")";
    if (auto near = nearest_key(s, allowed)) message += "; did you mean " + in_quotes(*near) + "?";
    ctx_->error(child(key), message);
    return std::nullopt;
  }
  return s;
}

std::optional<bool> ObjectReader::boolean(const std::string& key, Need need) {
  ctx_->record(key_info(child_pattern(key), "boolean", need == Need::kRequired));
  const json* v = lookup(key, need, "true or false");
  if (v == nullptr) return std::nullopt;
  if (!v->is_boolean()) {
    ctx_->error(child(key), "wrong type (got " + describe_value(*v) + ", expected true or false)");
    return std::nullopt;
  }
  return v->get<bool>();
}

std::optional<ObjectReader> ObjectReader::object(const std::string& key, Need need) {
  ctx_->record(key_info(child_pattern(key), "object", need == Need::kRequired));
  const json* v = lookup(key, need, "an object");
  if (v == nullptr) return std::nullopt;
  ObjectReader r(*ctx_, *v, child(key), child_pattern(key));
  if (!r.valid()) return std::nullopt;
  return r;
}

std::vector<ObjectReader> ObjectReader::objects(const std::string& key, Need need,
                                                std::size_t min_items) {
  KeyInfo info = key_info(child_pattern(key), "array", need == Need::kRequired);
  if (min_items > 0) info.min_items = min_items;
  ctx_->record(info);
  ctx_->record(key_info(child_pattern(key) + "/*", "object", false));
  std::vector<ObjectReader> out;
  const std::string expected = "an array of objects";
  const json* v = lookup(key, need, expected);
  if (v == nullptr) return out;
  if (!v->is_array()) {
    ctx_->error(child(key), "wrong type (got " + describe_value(*v) + ", expected " + expected + ")");
    return out;
  }
  if (v->size() < min_items) {
    ctx_->error(child(key), "too few items (got " + describe_value(*v) + ", expected at least " +
                                std::to_string(min_items) + ")");
    return out;
  }
  for (std::size_t i = 0; i < v->size(); ++i) {
    ObjectReader item(*ctx_, (*v)[i], child(key) + "/" + std::to_string(i), child_pattern(key) + "/*");
    if (item.valid()) out.push_back(std::move(item));
    if (ctx_->error_count() >= LoadContext::kMaxErrors) break;
  }
  return out;
}

const json* ObjectReader::raw(const std::string& key, Need need, const std::string& type,
                              const std::string& expected) {
  ctx_->record(key_info(child_pattern(key), type, need == Need::kRequired));
  return lookup(key, need, expected);
}

void ObjectReader::finish() {
  if (object_ == nullptr) return;
  for (auto it = object_->begin(); it != object_->end(); ++it) {
    if (std::find(asked_.begin(), asked_.end(), it.key()) != asked_.end()) continue;
    std::string message = "unknown key";
    if (auto near = nearest_key(it.key(), asked_)) {
      // Name every spelling of the quantity the suggestion belongs to.
      std::string names = in_quotes(*near);
      for (const auto& g : groups_) {
        if (std::find(g.begin(), g.end(), *near) == g.end()) continue;
        names.clear();
        for (std::size_t i = 0; i < g.size(); ++i) {
          names += (i == 0 ? "" : i + 1 == g.size() ? " or " : ", ") + in_quotes(g[i]);
        }
      }
      message += " (did you mean " + names + "?)";
    } else {
      message += " (expected one of:";
      for (std::size_t i = 0; i < asked_.size(); ++i) {
        message += (i == 0 ? " " : ", ") + in_quotes(asked_[i]);
      }
      message += ")";
    }
    ctx_->error(child(it.key()), message);
  }
}

}  // namespace acdr
