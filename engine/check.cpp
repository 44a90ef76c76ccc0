#include "engine/check.h"

#include <stdexcept>

namespace ringtol::internal {

std::string_view NextCheckedName(std::string_view& names) {
  int depth = 0;
  char quote = 0;
  std::size_t end = 0;
  for (; end < names.size(); ++end) {
    const char c = names[end];
    if (quote != 0) {
      if (c == '\\') ++end;
      else if (c == quote) quote = 0;
    } else if (c == '"' || c == '\'') {
      quote = c;
    } else if (c == '(' || c == '[' || c == '{') {
      ++depth;
    } else if (c == ')' || c == ']' || c == '}') {
      --depth;
    } else if (c == ',' && depth == 0) {
      break;
    }
  }
  std::string_view name = names.substr(0, end);
  names.remove_prefix(end < names.size() ? end + 1 : end);
  while (!name.empty() && name.front() == ' ') name.remove_prefix(1);
  while (!name.empty() && name.back() == ' ') name.remove_suffix(1);
  return name;
}

void ThrowCheckFailure(const char* condition, const char* function, const char* file, int line,
                       const std::string& values) {
  std::string message = std::string(file) + ":" + std::to_string(line) + ": " + function + ": check failed: " + condition;
  if (!values.empty()) message += " (" + values + ")";
  throw std::logic_error(message);
}

}  // namespace ringtol::internal
