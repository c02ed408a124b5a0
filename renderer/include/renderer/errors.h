// The typed errors the renderer throws. Callers (CLI, editor) turn them into one line or a modal;
// nothing in the renderer prints or exits.
#pragma once
#include <stdexcept>
#include <string>

namespace renderer {

// A file that cannot be read as what it claims to be. what() reads
// "<path>: field '<field>': <reason>" (or "<path>: <reason>" when no single field is at fault).
class LoadError : public std::runtime_error {
public:
    LoadError(std::string path, std::string field, std::string reason)
        : std::runtime_error(format(path, field, reason)), m_path(std::move(path)), m_field(std::move(field)),
          m_reason(std::move(reason)) {}
    const std::string& path() const { return m_path; }
    const std::string& field() const { return m_field; }
    const std::string& reason() const { return m_reason; }

    // Quoted input is cut to this many characters in what(): a 100 MB path in a session must not come
    // back as a 100 MB error line. path() and reason() keep the whole text.
    static constexpr size_t kQuoteLimit = 200;
    static std::string capped(const std::string& text, size_t limit = kQuoteLimit) {
        return text.size() <= limit ? text : text.substr(0, limit) + "... (" + std::to_string(text.size()) + " characters)";
    }

private:
    static std::string format(const std::string& path, const std::string& field, const std::string& reason) {
        const std::string where = capped(path);
        // A reason quotes input too (a value, a second path): it gets room for two quotes and its own words.
        const std::string why = capped(reason, 3 * kQuoteLimit);
        return field.empty() ? where + ": " + why : where + ": field '" + capped(field) + "': " + why;
    }
    std::string m_path, m_field, m_reason;
};

// A GL failure: context creation, shader compile/link, an error reported through KHR_debug.
class GlError : public std::runtime_error {
public:
    GlError(const std::string& stage, const std::string& message)
        : std::runtime_error(stage + ": " + message) {}
};

// Work stopped because its ProgressCallback returned false (the user cancelled it): not a failure to report.
class Cancelled : public std::runtime_error {
public:
    using std::runtime_error::runtime_error;
};

// A request the renderer cannot honour (bad settings, empty volume, sizes out of range).
class RenderError : public std::runtime_error {
public:
    using std::runtime_error::runtime_error;
};

} // namespace renderer
