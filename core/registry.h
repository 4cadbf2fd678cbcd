#pragma once
// Registries over a std::variant: every alternative T names itself with `static constexpr
// std::string_view kType` and builds itself with `static T create(args...)`. Registering a type is
// adding it to the variant; lookup by name needs no if/else chain. Per-ray code then dispatches
// statically with std::visit (docs/style.md, rule 5).

#include <optional>
#include <string>
#include <string_view>
#include <variant>

namespace sylva {

namespace detail {
template <typename Variant>
struct VariantRegistry;

template <typename... Types>
struct VariantRegistry<std::variant<Types...>> {
  template <typename... Args>
  static std::optional<std::variant<Types...>> create(std::string_view type, Args&&... args) {
    std::optional<std::variant<Types...>> out;
    // The first type whose name matches is created; the fold's value only stops the search.
    static_cast<void>(((type == Types::kType ? (out.emplace(Types::create(args...)), true) : false) || ...));
    return out;
  }
  static std::string names() {
    std::string s;
    ((s.append(s.empty() ? "\"" : ", \"").append(Types::kType).append("\"")), ...);
    return s;
  }
};
}  // namespace detail

// The alternative of `Variant` whose kType is `type`, made by its create(args...); nullopt when no
// alternative has that name.
template <typename Variant, typename... Args>
std::optional<Variant> create_registered(std::string_view type, Args&&... args) {
  return detail::VariantRegistry<Variant>::create(type, std::forward<Args>(args)...);
}

// The registered names, quoted and comma-separated, for error messages.
template <typename Variant>
std::string registered_names() {
  return detail::VariantRegistry<Variant>::names();
}

// The kType of the alternative `v` holds.
template <typename Variant>
std::string_view registered_name(const Variant& v) {
  return std::visit([](const auto& x) { return std::decay_t<decltype(x)>::kType; }, v);
}

}  // namespace sylva
