#include "ndtom_apps/json_writer.h"

#include <cmath>
#include <cstdio>
#include <stdexcept>

namespace ndtom::apps {

std::string jsonQuote(const std::string& text) {
  std::string q = "\"";
  for (const char c : text) {
    if (c == '"' || c == '\\') {
      q += '\\';
      q += c;
    } else if (static_cast<unsigned char>(c) < 0x20) {
      char buffer[8];
      std::snprintf(buffer, sizeof buffer, "\\u%04x", c);
      q += buffer;
    } else {
      q += c;
    }
  }
  return q + "\"";
}

JsonWriter::JsonWriter() {
  out_.precision(16);  // 16 significant digits: time stamps since 1970 to the microsecond
}

void JsonWriter::key(const std::string& k) {
  if (!first_) out_ << ",";
  if (!in_array_.empty()) out_ << "\n" << std::string(2 * in_array_.size(), ' ');
  if (!in_array_.empty() && !in_array_.back()) out_ << jsonQuote(k) << ": ";
  first_ = false;
}

void JsonWriter::open(const std::string& k, char bracket) {
  key(k);
  out_ << bracket;
  in_array_.push_back(bracket == '[');
  first_ = true;
}

void JsonWriter::close(char bracket) {
  if (in_array_.empty()) throw std::logic_error("JsonWriter: nothing to close");
  in_array_.pop_back();
  if (!first_) out_ << "\n" << std::string(2 * in_array_.size(), ' ');
  out_ << bracket;
  first_ = false;
}

void JsonWriter::beginObject(const std::string& k) {
  open(k, '{');
}
void JsonWriter::endObject() {
  close('}');
}
void JsonWriter::beginArray(const std::string& k) {
  open(k, '[');
}
void JsonWriter::endArray() {
  close(']');
}

void JsonWriter::field(const std::string& k, const std::string& value) {
  key(k);
  out_ << jsonQuote(value);
}

void JsonWriter::field(const std::string& k, double value) {
  key(k);
  if (std::isfinite(value))
    out_ << value;
  else
    out_ << "null";
}

void JsonWriter::field(const std::string& k, size_t value) {
  key(k);
  out_ << value;
}

void JsonWriter::field(const std::string& k, int value) {
  key(k);
  out_ << value;
}

void JsonWriter::field(const std::string& k, bool value) {
  key(k);
  out_ << (value ? "true" : "false");
}

std::string JsonWriter::str() const {
  if (!in_array_.empty()) throw std::logic_error("JsonWriter: unclosed object or array");
  return out_.str() + "\n";
}

}  // namespace ndtom::apps
