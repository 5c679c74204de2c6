/* json.c — JSON pieces for the desk tools (see json.h). */
#include "json.h"

#include <math.h>
#include <stdbool.h>

#include "verdict.h"

void af_json_string(FILE *out, const char *s)
{
  fputc('"', out);
  for (; *s; s++) {
    unsigned char ch = (unsigned char)*s;
    if (ch == '"' || ch == '\\')
      fprintf(out, "\\%c", ch);
    else if (ch < 0x20)
      fprintf(out, "\\u%04x", ch);
    else
      fputc(ch, out);
  }
  fputc('"', out);
}

void af_json_double(FILE *out, double v, int digits)
{
  if (isfinite(v))
    fprintf(out, "%.*g", digits, v);
  else
    fputs("null", out);
}

void af_json_flags(FILE *out, uint32_t flags)
{
  bool first = true;
  fputc('[', out);
  for (uint32_t bit = 1; bit != 0; bit <<= 1)
    if (flags & bit) {
      fprintf(out, "%s\"%s\"", first ? "" : ", ", af_verdict_flag_name((af_verdict_flag)bit));
      first = false;
    }
  fputc(']', out);
}
