// util/schema.h — settings described once. A schema is a list of fields of a settings struct S, each
// with its name (the Python keyword and the JSON key), its command-line flags, help text, range or set of
// allowed values, and how to reach it in S. The command line (cli/schema_cli.h) builds its options from
// a schema, the Python module (python/schema_py.h) takes keyword arguments and writes its docstrings
// through it, and toJson/fromJson write and read settings with it; defaults are S's own member
// initialisers, so a field's default is written once too. Layers define their schemas next to their
// settings (render/settings.h, study/config.h, estimators/options.h). Header-only, no dependencies
// beyond the standard library and nlohmann-json.
#pragma once

#include <nlohmann/json.hpp>

#include <algorithm>
#include <cstdint>
#include <functional>
#include <limits>
#include <optional>
#include <stdexcept>
#include <string>
#include <string_view>
#include <type_traits>
#include <variant>
#include <vector>

namespace symphong::schema {

/// Where a field is offered.
enum Where : unsigned { kCli = 1, kPython = 2, kJson = 4, kEverywhere = 7 };

/// A field read and written as text (an enum with names): get gives its name, set parses one and
/// throws std::invalid_argument with a message (what follows "key: ") for a bad one.
template <class S>
struct TextAccess {
    std::function<std::string(const S&)> get;
    std::function<void(S&, const std::string&)> set;
};

template <class S>
using Access =
    std::variant<std::function<int&(S&)>, std::function<std::uint32_t&(S&)>, std::function<std::uint64_t&(S&)>, std::function<double&(S&)>,
                 std::function<bool&(S&)>, std::function<std::string&(S&)>, std::function<std::vector<std::uint32_t>&(S&)>,
                 std::function<std::vector<int>&(S&)>, std::function<std::vector<double>&(S&)>, TextAccess<S>>;

/// Access to member m of S.
template <class S, class T>
Access<S> member(T S::*m) {
    return std::function<T&(S&)>([m](S& s) -> T& { return s.*m; });
}

/// Access to member m of S's member `outer` (settings nested in settings).
template <class S, class O, class T>
Access<S> member(O S::*outer, T O::*m) {
    return std::function<T&(S&)>([outer, m](S& s) -> T& { return (s.*outer).*m; });
}

/// Access through any path: ref<S>([](S& s) -> auto& { return s.a.b.c; }).
template <class S, class L>
Access<S> ref(L path) {
    using T = std::remove_reference_t<std::invoke_result_t<L, S&>>;
    return std::function<T&(S&)>(path);
}

template <class S>
struct Field {
    std::string key;    ///< Python keyword and JSON key
    std::string flags;  ///< command-line names, CLI11 style ("--max-depth,-d"); empty: not on the command line
    std::string help;
    Access<S> access;
    double lo = -std::numeric_limits<double>::infinity();  ///< numbers and list elements: inclusive range
    double hi = std::numeric_limits<double>::infinity();
    bool positive = false;                            ///< a number that must be > 0 (and finite)
    std::vector<int> oneOf;                           ///< an integer that must be one of these
    std::function<std::vector<std::string>()> names;  ///< command line: a name that must be one of these
    std::function<void(const std::string&)> check;    ///< a string's own check (throws std::invalid_argument)
    unsigned where = kEverywhere;
    std::string pythonKey;      ///< Python keyword when it differs from key (negated flags)
    bool negated = false;       ///< a bool that the command-line flag sets and Python names by its opposite
    bool showDefault = true;    ///< command line: show the default in --help
    bool nullable = false;      ///< Python: None stands for the default (an empty string)
    bool nameList = false;      ///< Python: a string "a,b" or a sequence of strings (joined with commas)
    bool pythonRange = true;    ///< false: Python leaves the range to the library's own check (its message)
    std::string typeName;       ///< command line: type name shown in --help (text fields)
    bool changesPixels = true;  ///< false: the field cannot change a pixel's value (threads, output, stop rules)

    Field(std::string k, std::string f, std::string h, Access<S> a)
        : key(std::move(k)), flags(std::move(f)), help(std::move(h)), access(std::move(a)) {}
    Field&& range(double l, double h) && {
        lo = l, hi = h;
        return std::move(*this);
    }
    Field&& mustBePositive() && {
        positive = true;
        return std::move(*this);
    }
    Field&& among(std::vector<int> values) && {
        oneOf = std::move(values);
        return std::move(*this);
    }
    Field&& namedFrom(std::function<std::vector<std::string>()> n) && {
        names = std::move(n);
        return std::move(*this);
    }
    Field&& checkedBy(std::function<void(const std::string&)> c) && {
        check = std::move(c);
        return std::move(*this);
    }
    Field&& only(unsigned w) && {
        where = w;
        return std::move(*this);
    }
    Field&& python(std::string k, bool negate) && {
        pythonKey = std::move(k), negated = negate;
        return std::move(*this);
    }
    Field&& noDefaultShown() && {
        showDefault = false;
        return std::move(*this);
    }
    Field&& orNone() && {
        nullable = true;
        return std::move(*this);
    }
    Field&& listOfNames() && {
        nameList = true;
        return std::move(*this);
    }
    Field&& rangeOnCommandLineOnly() && {
        pythonRange = false;
        return std::move(*this);
    }
    Field&& keepsPixels() && {
        changesPixels = false;
        return std::move(*this);
    }
    Field&& type(std::string t) && {
        typeName = std::move(t);
        return std::move(*this);
    }

    bool in(Where w) const { return (where & w) != 0; }
    const std::string& pyKey() const { return pythonKey.empty() ? key : pythonKey; }
    /// The first of the command-line names ("--max-depth" of "--max-depth,-d"; a positional's name).
    std::string flag() const { return flags.substr(0, flags.find(',')); }
    bool hasRange() const { return lo > -std::numeric_limits<double>::infinity() || hi < std::numeric_limits<double>::infinity(); }
};

template <class S>
using Schema = std::vector<Field<S>>;

/// The fields of a nested settings struct O, reached through S's member `outer`, keeping those whose key
/// is not in `except`.
template <class S, class O>
Schema<S> nested(const Schema<O>& inner, O S::*outer, const std::vector<std::string>& except = {}) {
    Schema<S> out;
    for (const Field<O>& f : inner) {
        bool skip = false;
        for (const std::string& e : except) skip = skip || e == f.key;
        if (skip) continue;
        Access<S> a = std::visit(
            [outer](const auto& in) -> Access<S> {
                using A = std::decay_t<decltype(in)>;
                if constexpr (std::is_same_v<A, TextAccess<O>>) {
                    return TextAccess<S>{[outer, in](const S& s) { return in.get(s.*outer); },
                                         [outer, in](S& s, const std::string& v) { in.set(s.*outer, v); }};
                } else {
                    using T = std::remove_reference_t<typename A::result_type>;
                    return std::function<T&(S&)>([outer, in](S& s) -> T& { return in(s.*outer); });
                }
            },
            f.access);
        Field<S> g(f.key, f.flags, f.help, std::move(a));
        g.lo = f.lo, g.hi = f.hi, g.positive = f.positive, g.oneOf = f.oneOf, g.names = f.names, g.check = f.check;
        g.where = f.where, g.pythonKey = f.pythonKey, g.negated = f.negated, g.showDefault = f.showDefault;
        g.nullable = f.nullable, g.nameList = f.nameList, g.pythonRange = f.pythonRange, g.typeName = f.typeName;
        g.changesPixels = f.changesPixels;
        out.push_back(std::move(g));
    }
    return out;
}

/// The value of field f of s as JSON.
template <class S>
nlohmann::json valueOf(const Field<S>& f, const S& s) {
    S& m = const_cast<S&>(s);  // the accessors hand out references; nothing is written
    return std::visit(
        [&](const auto& a) -> nlohmann::json {
            using A = std::decay_t<decltype(a)>;
            if constexpr (std::is_same_v<A, TextAccess<S>>)
                return a.get(s);
            else
                return a(m);
        },
        f.access);
}

/// Every JSON field of s, as an object keyed by the fields' keys.
template <class S>
nlohmann::json toJson(const S& s, const Schema<S>& schema) {
    nlohmann::json out = nlohmann::json::object();
    for (const Field<S>& f : schema)
        if (f.in(kJson)) out[f.key] = valueOf(f, s);
    return out;
}

/// The fields of s that can change pixel values (every field but those marked keepsPixels()), wherever
/// they are offered: what identifies a render's image (render/checkpoint.h).
template <class S>
nlohmann::json pixelSettingsJson(const S& s, const Schema<S>& schema) {
    nlohmann::json out = nlohmann::json::object();
    for (const Field<S>& f : schema)
        if (f.changesPixels) out[f.key] = valueOf(f, s);
    return out;
}

/// The command line that gives s: every field offered there whose value differs from a default S's, or
/// whose key is in `always`, in the schema's order, positional fields (flags without a dash) first as their
/// value, the others as "--flag value" (the first of a field's flags; lists joined with commas, a bool as
/// its flag when true; a bool that is false while its default is true cannot be given on the command
/// line and is left out). A value with a character a shell would read is single-quoted.
template <class S>
std::string commandLine(const S& s, const Schema<S>& schema, const std::vector<std::string>& always = {}) {
    const S defaults{};
    const auto quoted = [](const std::string& v) {
        if (!v.empty() && v.find_first_not_of("abcdefghijklmnopqrstuvwxyzABCDEFGHIJKLMNOPQRSTUVWXYZ0123456789-_.,/:+=@%") == std::string::npos)
            return v;
        std::string q(1, '\'');
        for (char c : v) {
            if (c == '\'')
                q.append("'\\''");
            else
                q.push_back(c);
        }
        q.push_back('\'');
        return q;
    };
    const auto text = [](const nlohmann::json& j) {
        if (j.is_string()) return j.get<std::string>();
        if (!j.is_array()) return j.dump();
        std::string joined;
        for (const nlohmann::json& e : j) {
            if (!joined.empty()) joined += ',';
            joined += e.is_string() ? e.get<std::string>() : e.dump();
        }
        return joined;
    };
    std::string positional, options;
    for (const Field<S>& f : schema) {
        if (!f.in(kCli) || f.flags.empty()) continue;
        const nlohmann::json value = valueOf(f, s);
        if (value == valueOf(f, defaults) && std::find(always.begin(), always.end(), f.key) == always.end()) continue;
        const std::string flag = f.flag();
        if (flag[0] != '-') {
            positional.push_back(' ');
            positional.append(quoted(text(value)));
        } else if (!value.is_boolean() || value.get<bool>()) {
            options.push_back(' ');
            options.append(flag);
            if (!value.is_boolean()) {
                options.push_back(' ');
                options.append(quoted(text(value)));
            }
        }
    }
    return positional + options;
}

/// Checks value v of field f against its range, its allowed values and its check; returns the message
/// (what follows "key: " or "key = v ") of the first failure, or nothing.
template <class S>
std::optional<std::string> rangeProblem(const Field<S>& f, double v) {
    if (f.positive && !(v > 0 && v < std::numeric_limits<double>::infinity())) return std::string("must be a positive number");
    if (f.hasRange() && !(v >= f.lo && v <= f.hi)) return std::string("out of range");
    if (!f.oneOf.empty()) {
        bool found = false;
        for (int x : f.oneOf) found = found || x == v;
        if (!found) return std::string("not allowed");
    }
    return std::nullopt;
}

/// Reads the fields of `j` (an object keyed by the fields' keys) into s: unknown keys, wrong types and
/// values out of range are std::invalid_argument naming the key; keys that are absent keep s's values.
template <class S>
void fromJson(const nlohmann::json& j, S& s, const Schema<S>& schema) {
    if (!j.is_object()) throw std::invalid_argument("settings must be a JSON object");
    for (auto it = j.begin(); it != j.end(); ++it) {
        const Field<S>* f = nullptr;
        for (const Field<S>& g : schema)
            if (g.in(kJson) && g.key == it.key()) f = &g;
        if (!f) throw std::invalid_argument("unknown setting '" + it.key() + "'");
        const nlohmann::json& v = it.value();
        const auto bad = [&](const std::string& why) { return std::invalid_argument(it.key() + ": " + why + " (got " + v.dump() + ")"); };
        std::visit(
            [&](const auto& a) {
                using A = std::decay_t<decltype(a)>;
                if constexpr (std::is_same_v<A, TextAccess<S>>) {
                    if (!v.is_string()) throw bad("expected a string");
                    try {
                        a.set(s, v.get<std::string>());
                    } catch (const std::invalid_argument& e) {
                        throw std::invalid_argument(it.key() + ": " + e.what());
                    }
                } else {
                    using T = std::remove_reference_t<typename A::result_type>;
                    if constexpr (std::is_same_v<T, bool>) {
                        if (!v.is_boolean()) throw bad("expected true or false");
                        a(s) = v.get<bool>();
                    } else if constexpr (std::is_same_v<T, std::string>) {
                        if (!v.is_string()) throw bad("expected a string");
                        if (f->check) f->check(v.get<std::string>());
                        a(s) = v.get<std::string>();
                    } else if constexpr (std::is_arithmetic_v<T>) {
                        if (!v.is_number() || (std::is_integral_v<T> && !v.is_number_integer())) throw bad("expected a number");
                        if (std::is_unsigned_v<T> && v.is_number_integer() && !v.is_number_unsigned()) throw bad("out of range");
                        if (auto p = rangeProblem(*f, v.get<double>())) throw bad(*p);
                        a(s) = v.get<T>();
                    } else {
                        using E = typename T::value_type;
                        if (!v.is_array()) throw bad("expected a list of numbers");
                        T out;
                        for (const auto& x : v) {
                            if (!x.is_number() || (std::is_integral_v<E> && !x.is_number_integer()))
                                throw bad("expected a list of numbers");
                            if (auto p = rangeProblem(*f, x.get<double>())) throw bad(*p);
                            out.push_back(x.get<E>());
                        }
                        a(s) = out;
                    }
                }
            },
            f->access);
    }
}

}  // namespace symphong::schema
