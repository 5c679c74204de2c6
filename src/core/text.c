/* text.c — truncating formatter for message and report texts. */
#include "text.h"

#include <stdarg.h>
#include <stdio.h>

void af_text(char *buf, size_t len, const char *fmt, ...)
{
  va_list ap;
  va_start(ap, fmt);
  vsnprintf(buf, len, fmt, ap);
  va_end(ap);
}
