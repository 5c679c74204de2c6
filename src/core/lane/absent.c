/* absent.c — a lane input that never started (absent.h). */
#include "absent.h"

#include "text.h"

bool af_absent(const af_stream *s, int64_t start_ns, int64_t now_ns, double warn_after_s)
{
  if (s->seen || !(warn_after_s > 0.0) || start_ns <= 0)
    return false;
  return (double)(now_ns - start_ns) >= warn_after_s * 1e9;
}

/* " (N refused: the last problem)" when s refused chunks, else "". */
static void refused(const af_stream *s, char *buf, size_t len)
{
  unsigned long long bad = (unsigned long long)af_stream_bad_chunks(s);
  if (bad == 0)
    buf[0] = '\0';
  else
    af_text(buf, len, " (%llu refused: %s)", bad, s->last_problem);
}

bool af_absent_warning(const af_stream *force, const af_stream *audio, int64_t start_ns,
                       int64_t now_ns, double warn_after_s, char *text, size_t len)
{
  const bool f = af_absent(force, start_ns, now_ns, warn_after_s);
  const bool a = af_absent(audio, start_ns, now_ns, warn_after_s);
  char why_f[AF_STREAM_TEXT_MAX + 32], why_a[AF_STREAM_TEXT_MAX + 32];
  if (len > 0)
    text[0] = '\0';
  if (!f && !a)
    return false;
  refused(force, why_f, sizeof why_f);
  refused(audio, why_a, sizeof why_a);
  if (f && a)
    af_text(text, len, "no force and no audio chunk within %.1f s of start%s%s", warn_after_s,
            why_f, why_a);
  else
    af_text(text, len, "no %s chunk within %.1f s of start%s", f ? "force" : "audio", warn_after_s,
            f ? why_f : why_a);
  return true;
}
