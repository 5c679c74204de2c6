/* text.c — truncating formatter for message and report texts. */
#include "text.h"

#include <stdarg.h>
#include <stdio.h>

void af_text(char *buf, size_t len, const char *fmt, ...)
{
  if (buf == NULL || len == 0) /* no room asked for: a caller's optional err */
    return;
  va_list ap;
  va_start(ap, fmt);
  vsnprintf(buf, len, fmt, ap);
  va_end(ap);
}

void af_text_line(char *buf, size_t len, const char *fmt, ...)
{
  if (buf == NULL || len == 0)
    return;
  va_list ap;
  va_start(ap, fmt);
  vsnprintf(buf, len, fmt, ap);
  va_end(ap);
  for (char *p = buf; *p; p++)
    if (af_text_is_control(*p))
      *p = '?';
}

bool af_text_is_control(char c)
{
  return (unsigned char)c < 0x20 || c == 0x7f;
}
