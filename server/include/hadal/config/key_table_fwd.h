// Declares config::KeyTable (config/key_table.h) for spec headers that name their key table without
// pulling in the YAML reader.
#pragma once

namespace hadal::config {

struct NoContext;
template <class T, class Ctx = NoContext>
class KeyTable;

}  // namespace hadal::config
