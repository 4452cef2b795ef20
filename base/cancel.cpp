#include "base/cancel.h"

#include <utility>

namespace obscura {

namespace {
thread_local CancelCheck tCheck;
} // namespace

CancelScope::CancelScope(CancelCheck check) : outer_(std::exchange(tCheck, std::move(check))) {}

CancelScope::~CancelScope() { tCheck = std::move(outer_); }

bool cancelRequested() { return tCheck && tCheck(); }

void throwIfCancelled() {
    if (cancelRequested()) throw Cancelled();
}

} // namespace obscura
