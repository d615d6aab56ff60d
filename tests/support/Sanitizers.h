// Whether this build runs under a sanitizer: AddressSanitizer and ThreadSanitizer reserve
// terabytes of address space for their shadow memory at start-up, so a test that limits the
// address space (setrlimit, ulimit -v) cannot run under them.
#pragma once

#if defined(__SANITIZE_ADDRESS__) || defined(__SANITIZE_THREAD__)
#define RENGINE_TEST_SANITIZED 1
#elif defined(__has_feature)
#if __has_feature(address_sanitizer) || __has_feature(thread_sanitizer) || __has_feature(memory_sanitizer)
#define RENGINE_TEST_SANITIZED 1
#endif
#endif
#ifndef RENGINE_TEST_SANITIZED
#define RENGINE_TEST_SANITIZED 0
#endif
