// Every relative link and image in README.md and docs/*.md resolves: the file exists, and a #anchor
// names a heading (GitHub's slug) or an id of the page it points at. http(s) and mailto links are
// skipped. Links are read from Markdown ([text](target), ![alt](target), [label]: target) and HTML
// (<img src>, <a href>) outside code blocks and code spans. An absolute path fails: a doc must not
// name a path of the machine it was written on.
// Its own small binary (doc_link_tests, label unit): it needs the source tree, not the renderer.
#include <gtest/gtest.h>

#include <algorithm>
#include <cctype>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <regex>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include <unistd.h>

namespace fs = std::filesystem;

namespace {

fs::path sourceDir() {
    if (const char* env = std::getenv("SPLATLAB_SOURCE_DIR"); env && *env) return env;
    return SPLATLAB_DEFAULT_SOURCE_DIR;
}

std::vector<std::string> readLines(const fs::path& file) {
    std::ifstream in(file);
    std::vector<std::string> lines;
    for (std::string line; std::getline(in, line);) lines.push_back(line);
    return lines;
}

std::string trimmed(const std::string& s) {
    const size_t b = s.find_first_not_of(" \t");
    return b == std::string::npos ? "" : s.substr(b);
}

bool isFence(const std::string& line) {
    const std::string t = trimmed(line);
    return t.rfind("```", 0) == 0 || t.rfind("~~~", 0) == 0;
}

// The line without its code spans (`x`, ``x``): what is inside them is not a link.
std::string withoutCodeSpans(const std::string& line) {
    std::string out;
    size_t i = 0;
    while (i < line.size()) {
        if (line[i] != '`') {
            out += line[i++];
            continue;
        }
        size_t run = 0;
        while (i + run < line.size() && line[i + run] == '`') ++run;
        const std::string ticks(run, '`');
        const size_t close = line.find(ticks, i + run);
        if (close == std::string::npos) {   // an unmatched tick is text
            out += ticks;
            i += run;
            continue;
        }
        out += ' ';
        i = close + run;
    }
    return out;
}

// GitHub's anchor for a heading: lower case, spaces to hyphens, punctuation other than - and _ dropped.
std::string slug(const std::string& text) {
    std::string out;
    for (unsigned char c : text) {
        if (std::isalnum(c) || c == '-' || c == '_' || c >= 0x80)
            out += char(std::tolower(c));
        else if (c == ' ')
            out += '-';
    }
    return out;
}

// Anchors a page offers: its headings' slugs (repeats get -1, -2, ...) and id/name attributes.
std::set<std::string> anchorsOf(const fs::path& file) {
    std::set<std::string> anchors;
    std::map<std::string, int> seen;
    bool fenced = false;
    static const std::regex idAttr(R"re(\b(?:id|name)\s*=\s*"([^"]+)")re");
    for (const std::string& line : readLines(file)) {
        if (isFence(line)) {
            fenced = !fenced;
            continue;
        }
        if (fenced) continue;
        if (line.rfind('#', 0) == 0) {
            const size_t text = line.find_first_not_of('#');
            if (text != std::string::npos && text <= 6 && line[text] == ' ') {
                std::string heading = line.substr(text + 1);
                // Code spans keep their words in the slug: drop only the ticks.
                heading.erase(std::remove(heading.begin(), heading.end(), '`'), heading.end());
                std::string s = slug(heading);
                const int n = seen[s]++;
                anchors.insert(n == 0 ? s : s + "-" + std::to_string(n));
            }
        }
        for (std::sregex_iterator it(line.begin(), line.end(), idAttr), end; it != end; ++it)
            anchors.insert((*it)[1].str());
    }
    return anchors;
}

struct Link {
    int line = 0;
    std::string target;
};

std::vector<Link> linksOf(const fs::path& file) {
    static const std::regex markdownLink(R"re(\]\(\s*<?([^)\s>]+)>?(?:\s+"[^"]*")?\s*\))re");
    static const std::regex referenceDef(R"re(^\s{0,3}\[[^\]]+\]:\s*<?([^\s>]+)>?)re");
    static const std::regex htmlLink(R"re(<(?:img|a|source)\b[^>]*?\b(?:src|href)\s*=\s*"([^"]+)")re",
                                     std::regex::icase);
    std::vector<Link> links;
    bool fenced = false;
    int number = 0;
    for (const std::string& raw : readLines(file)) {
        ++number;
        if (isFence(raw)) {
            fenced = !fenced;
            continue;
        }
        if (fenced) continue;
        const std::string line = withoutCodeSpans(raw);
        for (const std::regex* re : {&markdownLink, &referenceDef, &htmlLink})
            for (std::sregex_iterator it(line.begin(), line.end(), *re), end; it != end; ++it)
                links.push_back({number, (*it)[1].str()});
    }
    return links;
}

bool external(const std::string& target) {
    for (const char* scheme : {"http://", "https://", "mailto:"})
        if (target.rfind(scheme, 0) == 0) return true;
    return false;
}

std::string percentDecoded(const std::string& s) {
    std::string out;
    for (size_t i = 0; i < s.size(); ++i) {
        if (s[i] == '%' && i + 2 < s.size() && std::isxdigit(static_cast<unsigned char>(s[i + 1])) &&
            std::isxdigit(static_cast<unsigned char>(s[i + 2]))) {
            out += char(std::stoi(s.substr(i + 1, 2), nullptr, 16));
            i += 2;
        } else {
            out += s[i];
        }
    }
    return out;
}

// "FILE:LINE: TARGET: why" for every link of `file` that does not resolve.
std::vector<std::string> brokenLinks(const fs::path& file) {
    std::vector<std::string> broken;
    for (const Link& link : linksOf(file)) {
        if (external(link.target)) continue;
        const auto fail = [&](const std::string& why) {
            broken.push_back(file.filename().string() + ":" + std::to_string(link.line) + ": " + link.target + ": " +
                             why);
        };
        const size_t hash = link.target.find('#');
        const std::string path = percentDecoded(link.target.substr(0, hash));
        const std::string anchor = hash == std::string::npos ? "" : link.target.substr(hash + 1);
        if (!path.empty() && fs::path(path).is_absolute()) {
            fail("an absolute path");
            continue;
        }
        const fs::path target = path.empty() ? file : file.parent_path() / path;
        std::error_code ec;
        if (!fs::exists(target, ec)) {
            fail("no such file");
            continue;
        }
        if (!anchor.empty() && target.extension() == ".md" && !anchorsOf(target).count(anchor))
            fail("no heading or id '" + anchor + "' in " + target.filename().string());
    }
    return broken;
}

std::vector<fs::path> documentationPages() {
    const fs::path root = sourceDir();
    std::vector<fs::path> pages{root / "README.md"};
    std::vector<fs::path> docs;
    for (const auto& entry : fs::directory_iterator(root / "docs"))
        if (entry.is_regular_file() && entry.path().extension() == ".md") docs.push_back(entry.path());
    std::sort(docs.begin(), docs.end());
    pages.insert(pages.end(), docs.begin(), docs.end());
    return pages;
}

std::string joined(const std::vector<std::string>& lines) {
    std::ostringstream out;
    for (const std::string& l : lines) out << "\n  " << l;
    return out.str();
}

} // namespace

TEST(DocLinks, EveryRelativeLinkAndImageInTheReadmeAndDocsResolves) {
    const std::vector<fs::path> pages = documentationPages();
    ASSERT_TRUE(fs::exists(pages.front())) << pages.front() << " not found: set SPLATLAB_SOURCE_DIR";
    ASSERT_GT(pages.size(), 1u) << "no docs/*.md beside " << pages.front();
    std::vector<std::string> broken;
    size_t checked = 0;
    for (const fs::path& page : pages) {
        checked += linksOf(page).size();
        const std::vector<std::string> b = brokenLinks(page);
        broken.insert(broken.end(), b.begin(), b.end());
    }
    EXPECT_GT(checked, 20u) << "too few links found: is the parser reading the pages?";
    EXPECT_TRUE(broken.empty()) << broken.size() << " links do not resolve:" << joined(broken);
}

TEST(DocLinks, FindsAMissingFileAMissingAnchorAndAnAbsolutePath) {
    const fs::path dir = fs::temp_directory_path() / ("splatlab_doc_links_" + std::to_string(::getpid()));
    fs::create_directories(dir / "docs" / "images");
    std::ofstream(dir / "docs" / "images" / "a.png") << "png";
    std::ofstream(dir / "docs" / "page.md") << "# A page\n\n## Its `code` section, twice\n\n## Its `code` section, twice\n";
    std::ofstream(dir / "README.md")
        << "# Title\n\n![ok](docs/images/a.png) [ok](docs/page.md#its-code-section-twice-1) [ok](#title)\n"
           "[web](https://example.com/x) `[code](missing.md)`\n\n```sh\n[fenced](missing.md)\n```\n\n"
           "![gone](docs/images/b.png) [gone](docs/page.md#no-such-heading) [abs](/etc/hostname)\n"
           "<img src=\"docs/images/c.png\" width=\"9\">\n[def]: docs/nothing.md\n";
    const std::vector<std::string> broken = brokenLinks(dir / "README.md");
    fs::remove_all(dir);
    ASSERT_EQ(broken.size(), 5u) << joined(broken);
    EXPECT_NE(broken[0].find("docs/images/b.png: no such file"), std::string::npos) << broken[0];
    EXPECT_NE(broken[1].find("no heading or id 'no-such-heading'"), std::string::npos) << broken[1];
    EXPECT_NE(broken[2].find("an absolute path"), std::string::npos) << broken[2];
    EXPECT_NE(broken[3].find("docs/images/c.png"), std::string::npos) << broken[3];
    EXPECT_NE(broken[4].find("docs/nothing.md"), std::string::npos) << broken[4];
}
