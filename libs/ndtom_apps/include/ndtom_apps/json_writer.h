// A small writer of indented JSON objects: enough for the run summary, no parser needed.
#pragma once

#include <sstream>
#include <string>
#include <vector>

namespace ndtom::apps {

class JsonWriter {
 public:
  JsonWriter();
  void beginObject(const std::string& key = "");  ///< key is ignored at the top and in arrays
  void endObject();
  void beginArray(const std::string& key);
  void endArray();
  void field(const std::string& key, const std::string& value);
  void field(const std::string& key, const char* value) { field(key, std::string(value)); }
  void field(const std::string& key, double value);  ///< non-finite values are written as null
  void field(const std::string& key, size_t value);
  void field(const std::string& key, int value);
  void field(const std::string& key, bool value);
  /// The document; all objects and arrays must be closed.
  std::string str() const;

 private:
  void open(const std::string& key, char bracket);
  void close(char bracket);
  void key(const std::string& key);

  std::ostringstream out_;
  std::vector<bool> in_array_;  ///< per open level
  bool first_ = true;           ///< nothing written yet at this level
};

/// `text` as a JSON string literal, quotes included.
std::string jsonQuote(const std::string& text);

}  // namespace ndtom::apps
