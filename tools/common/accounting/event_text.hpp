/**
 * @file event_text.hpp
 * @brief The text of a flight event, filled from the template its declaration carries
 *        (fdir::EventInfo::text in fdir/event_ids.hpp).
 *
 * The template language is declared with EventInfo::text. A type named by @type is
 * one of kEventTextTypes: each gives the words of one kind of value (a supervisor
 * node, a policy alternative, a check of the filter's state), so the words are
 * written once, for every event that carries such a value.
 */
#pragma once

#include "fdir/event_log.hpp"

#include <cstddef>
#include <span>
#include <string>

namespace tools {

/**
 * Fills @p info's text from @p e's fields into @p out, NUL-terminated and cut to fit; no allocation.
 * A template fault (it cannot be: every template is checked by check_event_text in the tests)
 * prints "{?}" in place. @return the length written.
 */
std::size_t format_event_text(const fdir::EventInfo& info, const fdir::Event& e, std::span<char> out) noexcept;

/**
 * Checks a template: braces balanced, each placeholder a field (s c a b) with a known selector and
 * format, each @type known, nesting within the formatter's depth. @return "" or what is wrong.
 */
std::string check_event_text(const char* text);

/** The names @type may take, for the docs and the tests. */
std::span<const char* const> event_text_types() noexcept;

}  // namespace tools
