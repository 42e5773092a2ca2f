/**
 * @file message_doc.hpp
 * @brief The declared message kinds (trn/tasks/messages.hpp) as the Markdown rows of
 *        docs/ARCHITECTURE.md, "Message kinds".
 */
#pragma once

#include <string>

namespace tools {

/**
 * One row per kind, "| `name` | tag | channel | from | to | words | fields |",
 * newline-terminated, in the order of trn::tasks::kMessageKinds.
 */
std::string message_kinds_markdown();

}  // namespace tools
