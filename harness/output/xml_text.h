// Text inside XML attributes and elements (junit.xml files).
#pragma once

#include <string>

namespace hb {

/// The text with & < > " ' replaced by their XML entities.
std::string xml_escape(const std::string& text);

}  // namespace hb
