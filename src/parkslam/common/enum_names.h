#ifndef PARKSLAM_COMMON_ENUM_NAMES_H_
#define PARKSLAM_COMMON_ENUM_NAMES_H_

// Enums that options files and command lines spell by name. Such an enum
// has, beside it, `EnumNames(E)` returning every value with its name (found
// by argument-dependent lookup); these helpers read that one table.

#include <concepts>
#include <optional>
#include <string>
#include <string_view>
#include <type_traits>
#include <vector>

namespace parkslam {

template <typename E>
concept NamedEnum = std::is_enum_v<E> && requires(E e) {
  { EnumNames(e).begin()->first } -> std::convertible_to<E>;
  { EnumNames(e).begin()->second } -> std::convertible_to<std::string_view>;
};

// The value's name ("" for a value the table lacks).
template <NamedEnum E>
const char* EnumName(E value) {
  for (const auto& [e, name] : EnumNames(value)) {
    if (e == value) return name;
  }
  return "";
}

// The value of that name, if any.
template <NamedEnum E>
std::optional<E> EnumFromName(std::string_view name) {
  for (const auto& [e, known] : EnumNames(E{})) {
    if (name == known) return e;
  }
  return std::nullopt;
}

// Every name, in the table's order.
template <NamedEnum E>
std::vector<std::string> EnumNameList() {
  std::vector<std::string> names;
  for (const auto& [e, name] : EnumNames(E{})) names.emplace_back(name);
  return names;
}

// The names joined by ", ", for messages.
template <NamedEnum E>
std::string EnumNamesJoined() {
  std::string joined;
  for (const std::string& name : EnumNameList<E>()) joined += (joined.empty() ? "" : ", ") + name;
  return joined;
}

}  // namespace parkslam

#endif  // PARKSLAM_COMMON_ENUM_NAMES_H_
