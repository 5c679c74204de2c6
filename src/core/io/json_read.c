/* json_read.c — the strict JSON reader (see json_read.h). Recursive
 * descent, depth-bounded; nodes in one array grown by doubling. */
#include "json_read.h"

#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define AF_JSON_DEPTH_TEXT_(x) #x
#define AF_JSON_DEPTH_TEXT_OF(x) AF_JSON_DEPTH_TEXT_(x)
#define AF_JSON_DEPTH_TEXT AF_JSON_DEPTH_TEXT_OF(AF_JSON_DEPTH_MAX)

typedef struct {
  af_json_doc *doc;
  size_t pos;
  char *err;
  size_t errlen;
  bool nomem;
} parser;

static bool fail(parser *p, const char *cause)
{
  if (p->err && p->errlen)
    snprintf(p->err, p->errlen, "offset %zu: %s", p->pos, cause);
  return false;
}

static void skip_space(parser *p)
{
  const char *t = p->doc->text;
  while (p->pos < p->doc->len &&
         (t[p->pos] == ' ' || t[p->pos] == '\t' || t[p->pos] == '\n' || t[p->pos] == '\r'))
    p->pos++;
}

static size_t new_node(parser *p, af_json_type type)
{
  af_json_doc *d = p->doc;
  if (d->n == d->cap) {
    size_t cap = d->cap ? 2 * d->cap : 64;
    af_json_node *q = realloc(d->nodes, cap * sizeof *q);
    if (!q) {
      p->nomem = true;
      return SIZE_MAX;
    }
    d->nodes = q;
    d->cap = cap;
  }
  af_json_node *n = &d->nodes[d->n];
  memset(n, 0, sizeof *n);
  n->type = type;
  n->off = p->pos;
  return d->n++;
}

static bool literal(parser *p, const char *word, af_json_type type, size_t *out)
{
  size_t n = strlen(word);
  if (p->doc->len - p->pos < n || memcmp(p->doc->text + p->pos, word, n) != 0)
    return fail(p, "not a JSON value");
  if ((*out = new_node(p, type)) == SIZE_MAX)
    return fail(p, "out of memory");
  p->doc->nodes[*out].len = n;
  p->pos += n;
  return true;
}

static bool is_digit(char c)
{
  return c >= '0' && c <= '9';
}

/* digits+; false when there is none. */
static bool digits(parser *p)
{
  size_t start = p->pos;
  while (p->pos < p->doc->len && is_digit(p->doc->text[p->pos]))
    p->pos++;
  return p->pos > start;
}

static bool number(parser *p, size_t *out)
{
  const char *t = p->doc->text;
  size_t start = p->pos;
  if (p->pos < p->doc->len && t[p->pos] == '-')
    p->pos++;
  if (p->pos < p->doc->len && t[p->pos] == '0')
    p->pos++;
  else if (!digits(p))
    return fail(p, "a number needs a digit");
  if (p->pos < p->doc->len && t[p->pos] == '.') {
    p->pos++;
    if (!digits(p))
      return fail(p, "a digit must follow the decimal point");
  }
  if (p->pos < p->doc->len && (t[p->pos] == 'e' || t[p->pos] == 'E')) {
    p->pos++;
    if (p->pos < p->doc->len && (t[p->pos] == '+' || t[p->pos] == '-'))
      p->pos++;
    if (!digits(p))
      return fail(p, "a digit must follow the exponent");
  }
  size_t end = p->pos;
  p->pos = start;
  if ((*out = new_node(p, AF_JSON_NUMBER)) == SIZE_MAX)
    return fail(p, "out of memory");
  p->doc->nodes[*out].len = end - start;
  p->pos = end;
  return true;
}

static int hex_value(char c)
{
  if (c >= '0' && c <= '9')
    return c - '0';
  if (c >= 'a' && c <= 'f')
    return c - 'a' + 10;
  if (c >= 'A' && c <= 'F')
    return c - 'A' + 10;
  return -1;
}

/* The 4 hex digits at s into *u; false when they are not. */
static bool hex4(const char *s, size_t avail, unsigned *u)
{
  if (avail < 4)
    return false;
  *u = 0;
  for (int k = 0; k < 4; k++) {
    int h = hex_value(s[k]);
    if (h < 0)
      return false;
    *u = *u * 16 + (unsigned)h;
  }
  return true;
}

/* The escape at t[*i] (after the backslash) as a code point; *i moves past
 * it. -1: not an escape JSON has, or a lone surrogate. */
static long escape(const char *t, size_t len, size_t *i)
{
  static const char from[] = "\"\\/bfnrt", to[] = "\"\\/\b\f\n\r\t";
  const char *e = *i < len ? strchr(from, t[*i]) : NULL;
  if (e != NULL && *e != '\0') {
    (*i)++;
    return (unsigned char)to[e - from];
  }
  unsigned hi, lo;
  if (*i >= len || t[*i] != 'u' || !hex4(t + *i + 1, len - *i - 1, &hi))
    return -1;
  *i += 5;
  if (hi >= 0xDC00 && hi <= 0xDFFF)
    return -1;
  if (hi < 0xD800 || hi > 0xDBFF)
    return (long)hi;
  if (*i + 1 >= len || t[*i] != '\\' || t[*i + 1] != 'u' || !hex4(t + *i + 2, len - *i - 2, &lo) ||
      lo < 0xDC00 || lo > 0xDFFF)
    return -1;
  *i += 6;
  return 0x10000L + (((long)hi - 0xD800) << 10) + ((long)lo - 0xDC00);
}

/* A string's span (the opening quote at p->pos) into *off, *len. */
static bool string_span(parser *p, size_t *off, size_t *len)
{
  const char *t = p->doc->text;
  const size_t quote = p->pos;
  size_t i = ++p->pos;
  while (i < p->doc->len && t[i] != '"') {
    if ((unsigned char)t[i] < 0x20) {
      p->pos = i;
      return fail(p, "a control character inside a string (escape it)");
    }
    if (t[i] == '\\') {
      i++;
      if (escape(t, p->doc->len, &i) < 0) {
        p->pos = i;
        return fail(p, "not a JSON escape (or a lone surrogate)");
      }
    } else
      i++;
  }
  if (i >= p->doc->len) {
    p->pos = quote;
    return fail(p, "a string is not closed");
  }
  *off = p->pos;
  *len = i - p->pos;
  p->pos = i + 1;
  return true;
}

static bool value(parser *p, int depth, size_t *out);

/* The elements or members up to the closing bracket; the node is made. */
static bool container(parser *p, int depth, bool object, size_t *out)
{
  const char close = object ? '}' : ']';
  if ((*out = new_node(p, object ? AF_JSON_OBJECT : AF_JSON_ARRAY)) == SIZE_MAX)
    return fail(p, "out of memory");
  if (depth >= AF_JSON_DEPTH_MAX)
    return fail(p, "nested deeper than " AF_JSON_DEPTH_TEXT " levels");
  p->pos++;
  skip_space(p);
  size_t last = 0, count = 0;
  if (p->pos < p->doc->len && p->doc->text[p->pos] == close) {
    p->pos++;
    p->doc->nodes[*out].len = 2;
    return true;
  }
  for (;;) {
    size_t key_off = 0, key_len = 0, k;
    skip_space(p);
    if (object) {
      if (p->pos >= p->doc->len || p->doc->text[p->pos] != '"')
        return fail(p, "a member name (a string) is expected");
      if (!string_span(p, &key_off, &key_len))
        return false;
      skip_space(p);
      if (p->pos >= p->doc->len || p->doc->text[p->pos] != ':')
        return fail(p, "':' is expected after a member name");
      p->pos++;
    }
    if (!value(p, depth + 1, &k))
      return false;
    af_json_node *n = &p->doc->nodes[k];
    n->key_off = key_off;
    n->key_len = key_len;
    if (count++ == 0)
      p->doc->nodes[*out].child = k;
    else
      p->doc->nodes[last].next = k;
    last = k;
    skip_space(p);
    if (p->pos < p->doc->len && p->doc->text[p->pos] == ',') {
      p->pos++;
      continue;
    }
    if (p->pos < p->doc->len && p->doc->text[p->pos] == close)
      break;
    return fail(p, object ? "',' or '}' is expected" : "',' or ']' is expected");
  }
  p->pos++;
  af_json_node *c = &p->doc->nodes[*out];
  c->count = count;
  c->len = p->pos - c->off;
  return true;
}

static bool value(parser *p, int depth, size_t *out)
{
  skip_space(p);
  if (p->pos >= p->doc->len)
    return fail(p, "a value is expected (the text ends)");
  switch (p->doc->text[p->pos]) {
  case '{': return container(p, depth, true, out);
  case '[': return container(p, depth, false, out);
  case '"': {
    size_t off, len;
    if (!string_span(p, &off, &len))
      return false;
    if ((*out = new_node(p, AF_JSON_STRING)) == SIZE_MAX)
      return fail(p, "out of memory");
    p->doc->nodes[*out].off = off;
    p->doc->nodes[*out].len = len;
    return true;
  }
  case 't': return literal(p, "true", AF_JSON_TRUE, out);
  case 'f': return literal(p, "false", AF_JSON_FALSE, out);
  case 'n': return literal(p, "null", AF_JSON_NULL, out);
  default: return number(p, out);
  }
}

af_status af_json_parse(const char *text, size_t len, af_json_doc *doc, char *err, size_t errlen)
{
  memset(doc, 0, sizeof *doc);
  doc->text = text;
  doc->len = len;
  parser p = {doc, 0, err, errlen, false};
  size_t top;
  if (text == NULL || !value(&p, 0, &top))
    return p.nomem ? AF_ENOMEM : AF_EINVAL;
  skip_space(&p);
  if (p.pos != len) {
    fail(&p, "text after the JSON value");
    return AF_EINVAL;
  }
  return AF_OK;
}

void af_json_free(af_json_doc *doc)
{
  free(doc->nodes);
  doc->nodes = NULL;
  doc->n = doc->cap = 0;
}

size_t af_json_member(const af_json_doc *doc, size_t obj, const char *name)
{
  if (obj >= doc->n || doc->nodes[obj].type != AF_JSON_OBJECT)
    return 0;
  size_t n = strlen(name);
  for (size_t k = doc->nodes[obj].child; k != 0; k = doc->nodes[k].next) {
    const af_json_node *m = &doc->nodes[k];
    if (m->key_len == n && memcmp(doc->text + m->key_off, name, n) == 0)
      return k;
  }
  return 0;
}

bool af_json_number(const af_json_doc *doc, size_t k, bool null_is_nan, double *out)
{
  if (k >= doc->n)
    return false;
  const af_json_node *n = &doc->nodes[k];
  if (n->type == AF_JSON_NULL && null_is_nan) {
    *out = NAN;
    return true;
  }
  char buf[64];
  if (n->type != AF_JSON_NUMBER || n->len >= sizeof buf)
    return false;
  memcpy(buf, doc->text + n->off, n->len);
  buf[n->len] = '\0';
  char *end;
  errno = 0;
  double v = strtod(buf, &end);
  if (*end != '\0' || !isfinite(v))
    return false;
  *out = v;
  return true;
}

bool af_json_u64(const af_json_doc *doc, size_t k, uint64_t *out)
{
  if (k >= doc->n || doc->nodes[k].type != AF_JSON_NUMBER)
    return false;
  const af_json_node *n = &doc->nodes[k];
  uint64_t v = 0;
  for (size_t i = 0; i < n->len; i++) {
    char c = doc->text[n->off + i];
    if (!is_digit(c) || v > (UINT64_MAX - (uint64_t)(c - '0')) / 10)
      return false;
    v = v * 10 + (uint64_t)(c - '0');
  }
  *out = v;
  return n->len > 0;
}

/* Code point u as UTF-8 into buf at *at; false when it does not fit. */
static bool put_utf8(unsigned long u, char *buf, size_t len, size_t *at)
{
  unsigned char b[4];
  size_t n = u < 0x80 ? 1 : u < 0x800 ? 2 : u < 0x10000 ? 3 : 4;
  static const unsigned char lead[] = {0, 0, 0xC0, 0xE0, 0xF0};
  for (size_t i = n; i-- > 1; u >>= 6)
    b[i] = (unsigned char)(0x80 | (u & 0x3F));
  b[0] = (unsigned char)(n == 1 ? u : (lead[n] | u));
  if (*at + n >= len)
    return false;
  memcpy(buf + *at, b, n);
  *at += n;
  return true;
}

bool af_json_string_of(const af_json_doc *doc, size_t k, char *buf, size_t len)
{
  if (k >= doc->n || doc->nodes[k].type != AF_JSON_STRING || len == 0)
    return false;
  const af_json_node *n = &doc->nodes[k];
  const char *t = doc->text + n->off;
  size_t at = 0;
  for (size_t i = 0; i < n->len;) {
    if (t[i] != '\\') { /* raw bytes (UTF-8 already) are copied as they are */
      if (at + 1 >= len)
        return false;
      buf[at++] = t[i++];
      continue;
    }
    i++;
    long u = escape(t, n->len, &i);
    if (u < 0 || !put_utf8((unsigned long)u, buf, len, &at))
      return false;
  }
  buf[at] = '\0';
  return true;
}

const char *af_json_type_name(af_json_type t)
{
  static const char *const names[] = {"null",     "false",    "true",     "a number",
                                      "a string", "an array", "an object"};
  return (unsigned)t < sizeof names / sizeof names[0] ? names[t] : "?";
}
