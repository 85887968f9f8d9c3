// python/schema_py.h — keyword arguments through a settings schema (util/schema.h): each keyword that a
// field offers to Python is converted to the field's type (TypeError for a wrong type, as pybind11 gives
// it), checked against the field's range, allowed values and own check (ValueError naming the keyword:
// "spp = 0 must lie in [1, 1000000]"), and written into the settings; unknown keywords are a TypeError.
// The docstrings' signature line and list of keywords are generated from the same fields.
#pragma once

#include "io/input_error.h"
#include "util/schema.h"

#include <fmt/format.h>
#include <pybind11/pybind11.h>

#include <cmath>
#include <set>
#include <string>
#include <type_traits>
#include <vector>

namespace symphong {

namespace pyschema {

namespace py = pybind11;

template <class T>
T castOrTypeError(const py::handle& value, const std::string& key, const char* expected) {
    try {
        return py::cast<T>(value);
    } catch (const py::cast_error&) {
        throw py::type_error(
            fmt::format("{}: expected {}, got {}", key, expected, py::str(py::type::of(value).attr("__name__")).cast<std::string>()));
    }
}

inline std::string formatBound(double v) {
    return v == std::floor(v) && std::abs(v) < 1e15 ? fmt::format("{:.0f}", v) : fmt::format("{:g}", v);
}

/// A number's check against a field's range and allowed values: ValueError (InputError) naming the key.
template <class S>
void checkNumber(const schema::Field<S>& f, double v, const std::string& shown) {
    if (f.positive && !(v > 0 && std::isfinite(v))) throw InputError(fmt::format("{} = {} must be a positive number", f.pyKey(), shown));
    if (f.pythonRange && f.hasRange() && !(v >= f.lo && v <= f.hi))
        throw InputError(fmt::format("{} = {} must lie in [{}, {}]", f.pyKey(), shown, formatBound(f.lo), formatBound(f.hi)));
    if (!f.oneOf.empty()) {
        bool found = false;
        for (int x : f.oneOf) found = found || x == v;
        if (!found) throw InputError(fmt::format("{}: {} is not one of {}", f.pyKey(), shown, fmt::join(f.oneOf, ", ")));
    }
}

template <class T, class S>
T number(const schema::Field<S>& f, const py::handle& value) {
    if constexpr (std::is_same_v<T, std::uint64_t>) {
        if (!py::isinstance<py::int_>(value)) throw py::type_error(fmt::format("{}: expected an integer", f.pyKey()));
        const py::int_ v = py::reinterpret_borrow<py::int_>(value);
        const py::int_ zero(0), limit = py::int_(py::reinterpret_steal<py::object>(PyLong_FromUnsignedLongLong(~0ULL)));
        if (v < zero || v > limit)
            throw InputError(fmt::format("{} = {} must lie in [0, 2**64 - 1]", f.pyKey(), py::repr(v).cast<std::string>()));
        return v.cast<std::uint64_t>();
    } else if constexpr (std::is_integral_v<T>) {
        const long long v = castOrTypeError<long long>(value, f.pyKey(), "an integer");
        checkNumber(f, static_cast<double>(v), std::to_string(v));
        if (v < static_cast<long long>(std::numeric_limits<T>::min()) || v > static_cast<long long>(std::numeric_limits<T>::max()))
            throw InputError(fmt::format("{} = {} is out of range", f.pyKey(), v));
        return static_cast<T>(v);
    } else {
        if (py::isinstance<py::str>(value)) throw py::type_error(fmt::format("{}: expected a number, got a string", f.pyKey()));
        const double v = castOrTypeError<double>(value, f.pyKey(), "a number");
        checkNumber(f, v, fmt::format("{:g}", v));
        return v;
    }
}

/// One keyword argument into field f of s.
template <class S>
void apply(const schema::Field<S>& f, S& s, const py::handle& value) {
    std::visit(
        [&](const auto& access) {
            using A = std::decay_t<decltype(access)>;
            if constexpr (std::is_same_v<A, schema::TextAccess<S>>) {
                const std::string text = castOrTypeError<std::string>(value, f.pyKey(), "a string");
                try {
                    access.set(s, text);
                } catch (const std::invalid_argument& e) {
                    throw InputError(fmt::format("{}: {}", f.pyKey(), e.what()));
                }
            } else {
                using T = std::remove_reference_t<typename A::result_type>;
                T& target = access(s);
                if constexpr (std::is_same_v<T, bool>) {
                    const bool b = castOrTypeError<bool>(value, f.pyKey(), "True or False");
                    target = f.negated ? !b : b;
                } else if constexpr (std::is_same_v<T, std::string>) {
                    if (f.nullable && value.is_none()) {
                        target.clear();
                        return;
                    }
                    if (f.nameList && !py::isinstance<py::str>(value)) {
                        std::vector<std::string> names;
                        for (const py::handle item : value) names.push_back(castOrTypeError<std::string>(item, f.pyKey(), "a string"));
                        target = fmt::format("{}", fmt::join(names, ","));
                        return;
                    }
                    if (!py::isinstance<py::str>(value)) throw py::type_error(fmt::format("{}: expected a string", f.pyKey()));
                    const std::string text = value.cast<std::string>();
                    if (f.check) try {
                            f.check(text);
                        } catch (const std::invalid_argument& e) {
                            throw InputError(fmt::format("{}: {}", f.pyKey(), e.what()));
                        }
                    target = text;
                } else if constexpr (std::is_arithmetic_v<T>) {
                    target = number<T>(f, value);
                } else {  // a list: one number or a sequence of numbers
                    using E = typename T::value_type;
                    if (py::isinstance<py::str>(value)) throw py::type_error("expected a number or a sequence of numbers, got a string");
                    T out;
                    if (py::hasattr(value, "__iter__"))
                        for (const py::handle item : value) out.push_back(number<E>(f, item));
                    else
                        out.push_back(number<E>(f, value));
                    target = out;
                }
            }
        },
        f.access);
}

/// Every keyword of `kwargs` into s through `fields`; `function` names the caller in the TypeError for
/// an unknown keyword.
template <class S>
void applyKwargs(S& s, const schema::Schema<S>& fields, const py::dict& kwargs, const char* function) {
    for (const auto& [k, value] : kwargs) {
        const std::string key = py::str(k).cast<std::string>();
        const schema::Field<S>* field = nullptr;
        for (const schema::Field<S>& f : fields)
            if (f.in(schema::kPython) && f.pyKey() == key) field = &f;
        if (!field) throw py::type_error(fmt::format("{}() got an unexpected keyword argument '{}'", function, key));
        apply(*field, s, value);
    }
}

/// The schema keys of the keyword arguments given (a negated flag's keyword names its field's key).
template <class S>
std::set<std::string> givenKeys(const schema::Schema<S>& fields, const py::dict& kwargs) {
    std::set<std::string> given;
    for (const auto& item : kwargs) {
        const std::string key = py::str(item.first).cast<std::string>();
        for (const schema::Field<S>& f : fields)
            if (f.in(schema::kPython) && f.pyKey() == key) given.insert(f.key);
    }
    return given;
}

/// A Python literal for a field's default (its value in S{}).
template <class S>
std::string pythonDefault(const schema::Field<S>& f) {
    const S defaults{};
    const nlohmann::json v = schema::valueOf(f, defaults);
    if (v.is_boolean()) return (f.negated ? !v.get<bool>() : v.get<bool>()) ? "True" : "False";
    if (v.is_string()) return f.nullable && v.get<std::string>().empty() ? "None" : "'" + v.get<std::string>() + "'";
    if (v.is_array()) {
        std::vector<std::string> items;
        for (const auto& x : v) items.push_back(x.dump());
        return items.size() == 1 ? "(" + items[0] + ",)" : "(" + fmt::format("{}", fmt::join(items, ", ")) + ")";
    }
    return v.dump();
}

/// "key=default, key=default, ..." for the fields offered to Python, in schema order.
template <class S>
std::string signature(const schema::Schema<S>& fields) {
    std::vector<std::string> parts;
    for (const schema::Field<S>& f : fields)
        if (f.in(schema::kPython)) parts.push_back(f.pyKey() + "=" + pythonDefault(f));
    return fmt::format("{}", fmt::join(parts, ", "));
}

/// One paragraph per keyword: "  key=default  help" (help from the schema; a negated flag's help is
/// the command line's, for the opposite of the keyword).
template <class S>
std::string keywordHelp(const schema::Schema<S>& fields) {
    std::string out;
    for (const schema::Field<S>& f : fields) {
        if (!f.in(schema::kPython)) continue;
        out += fmt::format("  {}={}\n      {}{}\n", f.pyKey(), pythonDefault(f), f.negated ? "False: " : "", f.help);
    }
    return out;
}

}  // namespace pyschema
}  // namespace symphong
