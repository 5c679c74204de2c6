/* text.h — formatting into the fixed-size text fields of the messages. */
#ifndef AF_TEXT_H
#define AF_TEXT_H

#include <stdbool.h>
#include <stddef.h>

#ifdef __cplusplus
extern "C" {
#endif

/* snprintf into buf[len], cut at len - 1 characters. Operator texts and
 * reasons are capped by the message fields (AF_TEXT_MAX): a long one is
 * meant to be cut, never to overflow, so one place says so instead of
 * every call site silencing -Wformat-truncation. buf NULL or len 0:
 * nothing is written (an optional error text). */
void af_text(char *buf, size_t len, const char *fmt, ...)
#if defined(__GNUC__)
    __attribute__((format(printf, 3, 4)))
#endif
    ;

/* af_text for a one-line message that quotes what it was given (a path, a
 * flag's value, a file's text): control characters in the result show as
 * '?', so a newline in a name or a CR of a DOS file cannot split it. */
void af_text_line(char *buf, size_t len, const char *fmt, ...)
#if defined(__GNUC__)
    __attribute__((format(printf, 3, 4)))
#endif
    ;

/* A control character (below 0x20, or DEL): one that would split or garble
 * a one-line message quoting it (a newline in a flag's value, a CR of a DOS
 * file); where quoted, it is shown as '?'. */
bool af_text_is_control(char c);

#ifdef __cplusplus
}
#endif
#endif
