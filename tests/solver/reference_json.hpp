#pragma once
/// \file reference_json.hpp
/// Test helper: the numbers of the independent reference script
/// (shared/reference/lattice_reference.py, beside the project root) as parsed JSON.
/// The script runs once per build tree (about 5 s); its output is cached in the test work
/// folder and refreshed when the script changes.

#include <unistd.h>

#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <memory>
#include <sstream>
#include <stdexcept>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

namespace hexdem::test {

/// A parsed JSON value (objects keep their keys in file order).
struct Json {
  enum class Kind { Null, Boolean, Number, String, Array, Object };
  Kind kind = Kind::Null;
  bool boolean = false;
  double number = 0.0;
  std::string text;
  std::vector<Json> items;
  std::vector<std::pair<std::string, Json>> members;

  /// The member `key` of an object; throws if absent.
  const Json& operator[](std::string_view key) const {
    for (const auto& [name, value] : members)
      if (name == key) return value;
    throw std::runtime_error("JSON: no member '" + std::string(key) + "'");
  }
  [[nodiscard]] bool is_null() const { return kind == Kind::Null; }
  [[nodiscard]] double num() const {
    if (kind != Kind::Number) throw std::runtime_error("JSON: not a number");
    return number;
  }
};

namespace detail {

class JsonParser {
 public:
  explicit JsonParser(std::string_view text) : text_(text) {}

  Json parse() {
    Json value = parse_value();
    skip_space();
    if (pos_ != text_.size()) error("trailing characters");
    return value;
  }

 private:
  [[noreturn]] void error(const std::string& what) const {
    throw std::runtime_error("JSON: " + what + " at offset " + std::to_string(pos_));
  }
  void skip_space() {
    while (pos_ < text_.size() && (text_[pos_] == ' ' || text_[pos_] == '\n' ||
                                   text_[pos_] == '\r' || text_[pos_] == '\t'))
      ++pos_;
  }
  bool consume(std::string_view token) {
    if (text_.substr(pos_, token.size()) != token) return false;
    pos_ += token.size();
    return true;
  }
  void expect(char c) {
    skip_space();
    if (pos_ >= text_.size() || text_[pos_] != c) error(std::string("expected '") + c + "'");
    ++pos_;
  }

  std::string parse_string() {
    expect('"');
    std::string out;
    while (pos_ < text_.size() && text_[pos_] != '"') {
      char c = text_[pos_++];
      if (c == '\\') {
        if (pos_ >= text_.size()) error("bad escape");
        const char e = text_[pos_++];
        if (e == 'n')
          c = '\n';
        else if (e == 't')
          c = '\t';
        else if (e == 'u') {  // only ASCII escapes are needed here
          c = static_cast<char>(std::stoi(std::string(text_.substr(pos_, 4)), nullptr, 16));
          pos_ += 4;
        } else
          c = e;
      }
      out += c;
    }
    expect('"');
    return out;
  }

  Json parse_value() {
    skip_space();
    if (pos_ >= text_.size()) error("unexpected end");
    Json value;
    const char c = text_[pos_];
    if (c == '{') {
      value.kind = Json::Kind::Object;
      ++pos_;
      skip_space();
      if (consume("}")) return value;
      do {
        std::string key = parse_string();
        expect(':');
        value.members.emplace_back(std::move(key), parse_value());
        skip_space();
      } while (consume(","));
      expect('}');
    } else if (c == '[') {
      value.kind = Json::Kind::Array;
      ++pos_;
      skip_space();
      if (consume("]")) return value;
      do {
        value.items.push_back(parse_value());
        skip_space();
      } while (consume(","));
      expect(']');
    } else if (c == '"') {
      value.kind = Json::Kind::String;
      value.text = parse_string();
    } else if (consume("null")) {
      value.kind = Json::Kind::Null;
    } else if (consume("true")) {
      value.kind = Json::Kind::Boolean;
      value.boolean = true;
    } else if (consume("false")) {
      value.kind = Json::Kind::Boolean;
    } else {
      std::size_t used = 0;
      value.kind = Json::Kind::Number;
      value.number = std::stod(std::string(text_.substr(pos_, 40)), &used);
      pos_ += used;
    }
    return value;
  }

  std::string_view text_;
  std::size_t pos_ = 0;
};

inline std::string run_command(const std::string& command) {
  std::unique_ptr<FILE, int (*)(FILE*)> pipe(popen(command.c_str(), "r"), pclose);
  if (!pipe) throw std::runtime_error("cannot run: " + command);
  std::string out;
  char buffer[4096];
  while (const std::size_t n = std::fread(buffer, 1, sizeof buffer, pipe.get()))
    out.append(buffer, n);
  return out;
}

}  // namespace detail

inline Json parse_json(std::string_view text) {
  return detail::JsonParser(text).parse();
}

/// Path of the reference script.
inline std::string reference_script() {
  return HEXDEM_SOURCE_DIR "/../shared/reference/lattice_reference.py";
}

/// Output of a Python snippet run by the system Python with the reference folder on sys.path
/// (`import lattice_reference as L`).
inline std::string run_reference_python(const std::string& code) {
  const std::string folder = std::filesystem::path(reference_script()).parent_path().string();
  return detail::run_command("'" HEXDEM_SYSTEM_PYTHON "' -c \"import sys; sys.path.insert(0, '" +
                             folder + "'); import lattice_reference as L; " + code + "\"");
}

/// `lattice_reference.py --json`, parsed (cached per test program and in the work folder).
inline const Json& lattice_reference() {
  static const Json json = [] {
    namespace fs = std::filesystem;
    const fs::path script = reference_script();
    if (!fs::exists(script))
      throw std::runtime_error("reference script not found: " + script.string());
    const fs::path cache = fs::path(HEXDEM_TEST_WORK_DIR) / "lattice_reference.json";
    std::string text;
    if (fs::exists(cache) && fs::last_write_time(cache) >= fs::last_write_time(script)) {
      std::ifstream in(cache);
      std::ostringstream contents;
      contents << in.rdbuf();
      text = contents.str();
    }
    if (text.empty()) {
      text = detail::run_command("'" HEXDEM_SYSTEM_PYTHON "' '" + script.string() + "' --json");
      // Write then rename, so that test programs running side by side never see half a file.
      const fs::path temporary = cache.string() + "." + std::to_string(::getpid()) + ".tmp";
      std::ofstream(temporary) << text;
      fs::rename(temporary, cache);
    }
    return parse_json(text);
  }();
  return json;
}

}  // namespace hexdem::test
