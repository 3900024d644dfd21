#include "report/html.hpp"

#include "common/csv.hpp"

#include <unistd.h>

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <regex>
#include <sstream>
#include <stdexcept>

namespace ricochet::report {

std::string html_escape(std::string_view text) {
  std::string out;
  out.reserve(text.size());
  for (char c : text) {
    switch (c) {
      case '&':
        out += "&amp;";
        break;
      case '<':
        out += "&lt;";
        break;
      case '>':
        out += "&gt;";
        break;
      case '"':
        out += "&quot;";
        break;
      case '\'':
        out += "&#39;";
        break;
      default:
        out += c;
    }
  }
  return out;
}

std::string base64(std::string_view bytes) {
  static const char* table = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
  std::string out;
  out.reserve((bytes.size() + 2) / 3 * 4);
  std::size_t i = 0;
  for (; i + 2 < bytes.size(); i += 3) {
    const unsigned v = (static_cast<unsigned char>(bytes[i]) << 16) |
                       (static_cast<unsigned char>(bytes[i + 1]) << 8) |
                       static_cast<unsigned char>(bytes[i + 2]);
    out += table[(v >> 18) & 63];
    out += table[(v >> 12) & 63];
    out += table[(v >> 6) & 63];
    out += table[v & 63];
  }
  const std::size_t rest = bytes.size() - i;
  if (rest > 0) {
    unsigned v = static_cast<unsigned char>(bytes[i]) << 16;
    if (rest == 2) v |= static_cast<unsigned char>(bytes[i + 1]) << 8;
    out += table[(v >> 18) & 63];
    out += table[(v >> 12) & 63];
    out += rest == 2 ? table[(v >> 6) & 63] : '=';
    out += '=';
  }
  return out;
}

namespace {

bool looks_numeric(const std::string& s) {
  if (s.empty()) return false;
  char* end = nullptr;
  std::strtod(s.c_str(), &end);
  return end && *end == '\0';
}

}  // namespace

HtmlPage::HtmlPage(std::string title) : title_(std::move(title)) {}

void HtmlPage::heading(int level, const std::string& text, const std::string& id) {
  level = std::clamp(level, 1, 4);
  body_ += "<h" + std::to_string(level);
  if (!id.empty()) {
    body_ += " id=\"" + html_escape(id) + "\"";
    if (level == 2) toc_.emplace_back(id, text);
  }
  body_ += ">" + html_escape(text) + "</h" + std::to_string(level) + ">\n";
}

void HtmlPage::begin_details(const std::string& summary) {
  body_ += "<details><summary>" + html_escape(summary) + "</summary>\n";
  ++open_details_;
}

void HtmlPage::end_details() {
  if (open_details_ == 0) throw std::logic_error("HtmlPage::end_details without begin_details");
  body_ += "</details>\n";
  --open_details_;
}

void HtmlPage::paragraph(const std::string& text) {
  body_ += "<p>" + html_escape(text) + "</p>\n";
}

void HtmlPage::verdict(const std::string& text) {
  body_ += "<p class=\"verdict\">" + html_escape(text) + "</p>\n";
}

void HtmlPage::labelled(const std::string& label, const std::string& text) {
  body_ += "<p><strong>" + html_escape(label) + ":</strong> " + html_escape(text) + "</p>\n";
}

void HtmlPage::list(const std::vector<std::string>& items) {
  body_ += "<ul>\n";
  for (const auto& i : items) body_ += "<li>" + html_escape(i) + "</li>\n";
  body_ += "</ul>\n";
}

void HtmlPage::table(const std::vector<std::string>& header,
                     const std::vector<std::vector<std::string>>& rows,
                     const std::string& caption) {
  body_ += "<table>\n";
  if (!caption.empty()) body_ += "<caption>" + html_escape(caption) + "</caption>\n";
  body_ += "<thead><tr>";
  for (const auto& h : header) body_ += "<th>" + html_escape(h) + "</th>";
  body_ += "</tr></thead>\n<tbody>\n";
  for (const auto& r : rows) {
    body_ += "<tr>";
    for (const auto& c : r)
      body_ +=
          std::string(looks_numeric(c) ? "<td class=\"num\">" : "<td>") + html_escape(c) + "</td>";
    body_ += "</tr>\n";
  }
  body_ += "</tbody></table>\n";
}

void HtmlPage::preformatted(const std::string& text) {
  body_ += "<pre>" + html_escape(text) + "</pre>\n";
}

namespace {

/// Big-endian 32-bit integer at `at` of a PNG header.
std::uint32_t be32(const std::string& b, std::size_t at) {
  std::uint32_t v = 0;
  for (std::size_t i = 0; i < 4; ++i) v = (v << 8) | static_cast<unsigned char>(b[at + i]);
  return v;
}

}  // namespace

std::string compact_svg(std::string_view svg) {
  std::string out(svg);
  for (bool changed = true; changed;) {  // a group that held only empty groups is empty next pass
    changed = false;
    std::string next;
    next.reserve(out.size());
    std::size_t i = 0;
    while (i < out.size()) {
      const std::size_t open = out.find("<g", i);
      if (open == std::string::npos) {
        next.append(out, i, std::string::npos);
        break;
      }
      const char after = open + 2 < out.size() ? out[open + 2] : '\0';
      const std::size_t close = out.find('>', open);
      if ((after == '>' || std::isspace(static_cast<unsigned char>(after))) &&
          close != std::string::npos && out[close - 1] != '/') {
        std::size_t k = close + 1;
        while (k < out.size() && std::isspace(static_cast<unsigned char>(out[k]))) ++k;
        if (out.compare(k, 4, "</g>") == 0) {
          next.append(out, i, open - i);
          i = k + 4;
          if (i < out.size() && out[i] == '\n') ++i;
          changed = true;
          continue;
        }
      }
      next.append(out, i, open + 2 - i);
      i = open + 2;
    }
    out.swap(next);
  }
  return out;
}

void HtmlPage::figure_file(const std::string& path, const std::string& caption) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw std::runtime_error("report: cannot read the figure " + path);
  std::ostringstream ss;
  ss << in.rdbuf();
  const std::string bytes = ss.str();
  // Intended size: the SVG's viewBox or the PNG's IHDR chunk (PNG spec, section 11.2.2), so
  // that the image keeps its aspect and never collapses to zero size.
  std::string size, mime;
  static const std::string kPng = "\x89PNG\r\n\x1a\n";
  if (bytes.rfind(kPng, 0) == 0 && bytes.size() >= 24 && bytes.compare(12, 4, "IHDR") == 0) {
    mime = "image/png";
    size = " width=\"" + std::to_string(be32(bytes, 16)) + "\" height=\"" +
           std::to_string(be32(bytes, 20)) + "\"";
  } else if (bytes.find("<svg") != std::string::npos) {
    mime = "image/svg+xml";
    std::smatch m;
    static const std::regex view_box(
        R"re(viewBox="\s*[-0-9.]+\s+[-0-9.]+\s+([0-9.]+)\s+([0-9.]+)")re");
    if (std::regex_search(bytes, m, view_box))
      size = " width=\"" + m[1].str() + "\" height=\"" + m[2].str() + "\"";
  } else {
    throw std::runtime_error("report: " + path + " is neither an SVG nor a PNG file");
  }
  const std::string embedded = mime == "image/svg+xml" ? compact_svg(bytes) : bytes;
  ++figures_;
  body_ += "<figure id=\"figure-" + std::to_string(figures_) + "\"><img class=\"fig\" alt=\"" +
           html_escape(caption) + "\"" + size + " src=\"data:" + mime + ";base64," +
           base64(embedded) + "\"><figcaption>Figure " + std::to_string(figures_) + ". " +
           html_escape(caption) + "</figcaption></figure>\n";
}

void HtmlPage::figure(const Figure& fig, const std::string& caption) {
  namespace fs = std::filesystem;
  std::string tmpl = (fs::temp_directory_path() / "ricochet-report-XXXXXX").string();
  std::vector<char> buf(tmpl.begin(), tmpl.end());
  buf.push_back('\0');
  if (mkdtemp(buf.data()) == nullptr)
    throw std::runtime_error(std::string("report: cannot create a temporary directory: ") +
                             std::strerror(errno));
  const fs::path dir = buf.data();
  try {
    // Grids of many panels are mostly axes, ticks and grid lines, pictures of grains mostly
    // discs: as SVG they made the page 7 MB; as PNG they are a few times smaller and read the
    // same on a screen.
    std::size_t points = 0;
    for (const auto& p : fig.panels)
      for (const auto& sr : p.series) points += sr.x.size();
    const bool raster = fig.panels.size() > kMaxVectorPanels || points > kMaxVectorPoints;
    const std::string path = (dir / (raster ? "figure.png" : "figure.svg")).string();
    render(fig, path);
    figure_file(path, caption);
  } catch (...) {
    std::error_code ec;
    fs::remove_all(dir, ec);
    throw;
  }
  std::error_code ec;
  fs::remove_all(dir, ec);
}

std::string HtmlPage::html() const {
  std::string out =
      "<!DOCTYPE html>\n<html lang=\"en\">\n<head>\n<meta charset=\"utf-8\">\n"
      "<meta name=\"viewport\" content=\"width=device-width, initial-scale=1\">\n<title>" +
      html_escape(title_) +
      "</title>\n<style>\n"
      "body{font-family:sans-serif;max-width:1250px;margin:2em auto;padding:0 1em;color:#222;"
      "line-height:1.45}\n"
      "h1{border-bottom:2px solid #444}h2{border-bottom:1px solid #aaa;margin-top:2em}\n"
      "table{border-collapse:collapse;margin:1em 0;font-size:0.92em}\n"
      "th,td{border:1px solid #bbb;padding:0.25em 0.6em;vertical-align:top}\n"
      "th{background:#eee}td.num{text-align:right;font-variant-numeric:tabular-nums}\n"
      "caption{caption-side:top;text-align:left;font-style:italic;padding-bottom:0.3em}\n"
      "figure{margin:1.5em 0}img.fig{max-width:100%;height:auto;border:1px solid #ddd}\n"
      "figcaption{font-size:0.9em;color:#444}pre{background:#f6f6f6;padding:0.6em;"
      "overflow-x:auto}\n"
      "details{margin:1em 0;border-left:3px solid #ccc;padding-left:0.8em}"
      "summary{cursor:pointer;color:#1f4e8c;font-weight:bold}\n"
      "p.verdict{font-size:1.1em;background:#f3f6fa;padding:0.6em;border-left:4px solid #1f4e8c}\n"
      "</style>\n</head>\n<body>\n<h1>" +
      html_escape(title_) + "</h1>\n";
  if (!toc_.empty()) {
    out += "<nav><strong>Contents</strong><ol>\n";
    for (const auto& [id, text] : toc_)
      out += "<li><a href=\"#" + html_escape(id) + "\">" + html_escape(text) + "</a></li>\n";
    out += "</ol></nav>\n";
  }
  out += body_;
  for (int i = 0; i < open_details_; ++i) out += "</details>\n";  // a block left open
  out += "</body>\n</html>\n";
  return out;
}

void HtmlPage::write(const std::string& path) const {
  namespace fs = std::filesystem;
  const fs::path p(path);
  if (p.has_parent_path()) fs::create_directories(p.parent_path());
  write_text_file(path, html(), "--out");
}

}  // namespace ricochet::report
