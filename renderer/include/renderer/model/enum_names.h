// Names of enum values as users type them (command line, sessions) and back: one rule for every
// enum that has a nameOf() function.
#pragma once
#include "renderer/errors.h"

#include <initializer_list>
#include <string>

namespace renderer {

// The value among `values` whose nameOf() is `name`; throws RenderError "unknown <what> 'name'
// (known: a, b, c)".
template <class E>
E enumFromName(const std::string& name, std::initializer_list<E> values, const char* (*nameOf)(E), const char* what) {
    std::string known;
    for (E v : values) {
        if (name == nameOf(v)) return v;
        known += (known.empty() ? "" : ", ") + std::string(nameOf(v));
    }
    throw RenderError(std::string("unknown ") + what + " '" + name + "' (known: " + known + ")");
}

} // namespace renderer
