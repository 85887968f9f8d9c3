// cli/schema_cli.h — the command line's options built from a settings schema (util/schema.h): one CLI11
// option per field that is offered on the command line, with its flags, help, range or allowed values
// (checked by CLI11 as the arguments are parsed) and its default shown in --help.
#pragma once

#include "util/schema.h"

#include <CLI/CLI.hpp>

#include <set>
#include <string>
#include <type_traits>

namespace symphong {

/// The keys of the fields whose options the command line gave (after parsing).
template <class S>
std::set<std::string> givenKeys(const CLI::App* cmd, const schema::Schema<S>& fields) {
    std::set<std::string> given;
    for (const schema::Field<S>& f : fields) {
        if (!f.in(schema::kCli) || f.flags.empty()) continue;
        const std::string first = f.flag();
        if (const CLI::Option* opt = cmd->get_option_no_throw(first); opt && opt->count() > 0) given.insert(f.key);
    }
    return given;
}

template <class S>
void addSchemaOptions(CLI::App* cmd, S& target, const schema::Schema<S>& fields) {
    for (const schema::Field<S>& f : fields) {
        if (!f.in(schema::kCli) || f.flags.empty()) continue;
        std::visit(
            [&](const auto& access) {
                using A = std::decay_t<decltype(access)>;
                if constexpr (std::is_same_v<A, schema::TextAccess<S>>) {
                    const std::string flag = f.flag();
                    cmd->add_option_function<std::string>(
                           f.flags,
                           [&target, access, flag](const std::string& value) {
                               try {
                                   access.set(target, value);
                               } catch (const std::invalid_argument& e) {
                                   throw CLI::ValidationError(flag, e.what());
                               }
                           },
                           f.help)
                        ->type_name(f.typeName);
                } else {
                    using T = std::remove_reference_t<typename A::result_type>;
                    T& value = access(target);
                    if constexpr (std::is_same_v<T, bool>) {
                        cmd->add_flag(f.flags, value, f.help);
                    } else {
                        CLI::Option* opt = cmd->add_option(f.flags, value, f.help);
                        if constexpr (std::is_arithmetic_v<T>) {
                            if (f.hasRange()) opt->check(CLI::Range(static_cast<T>(f.lo), static_cast<T>(f.hi)));
                            if (f.positive) opt->check(CLI::PositiveNumber);
                            if (!f.oneOf.empty()) opt->check(CLI::IsMember(f.oneOf));
                        } else if constexpr (!std::is_same_v<T, std::string>) {  // lists
                            using E = typename T::value_type;
                            opt->delimiter(',');
                            if (f.hasRange()) opt->check(CLI::Range(static_cast<E>(f.lo), static_cast<E>(f.hi)));
                        }
                        if (f.names) opt->check(CLI::IsMember(f.names()));
                        if (f.showDefault) opt->capture_default_str();
                    }
                }
            },
            f.access);
    }
}

}  // namespace symphong
