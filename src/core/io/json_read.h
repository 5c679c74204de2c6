/* json_read.h — a strict JSON reader (RFC 8259) for the desk tools'
 * own documents: firmness_report --merge reads the per-bag reports back.
 *
 * The text is parsed once into a flat array of nodes that point into it
 * (no copy of strings or numbers); a value is then read on demand. Depth is
 * bounded (AF_JSON_DEPTH_MAX) and the node array grows with the text, so
 * memory is bounded by the caller's bound on the text's size. Refused, with
 * one line naming the byte offset and the cause: anything that is not JSON
 * (trailing commas, comments, NaN, single quotes, a control character in a
 * string, a lone surrogate escape), trailing text after the value, and a
 * nesting deeper than the bound. */
#ifndef AF_JSON_READ_H
#define AF_JSON_READ_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#include "status.h"

#ifdef __cplusplus
extern "C" {
#endif

#define AF_JSON_DEPTH_MAX 64

typedef enum {
  AF_JSON_NULL,
  AF_JSON_FALSE,
  AF_JSON_TRUE,
  AF_JSON_NUMBER,
  AF_JSON_STRING,
  AF_JSON_ARRAY,
  AF_JSON_OBJECT
} af_json_type;

typedef struct {
  af_json_type type;
  size_t off, len;         /* the value's text (a string: inside its quotes) */
  size_t key_off, key_len; /* an object member's name, inside its quotes; else 0, 0 */
  size_t child;            /* the first element or member (0: none) */
  size_t next;             /* the next sibling (0: the last) */
  size_t count;            /* elements or members of an array or object */
} af_json_node;

typedef struct {
  const char *text; /* borrowed: must outlive the document */
  size_t len;
  af_json_node *nodes; /* nodes[0] is the top value */
  size_t n, cap;
} af_json_doc;

/* Parses text[0..len) into *doc (which then borrows text). AF_OK; AF_EINVAL
 * with "offset N: cause" in err; AF_ENOMEM. Free with af_json_free even on
 * failure. */
af_status af_json_parse(const char *text, size_t len, af_json_doc *doc, char *err, size_t errlen);
void af_json_free(af_json_doc *doc); /* safe twice, and on a zeroed doc */

/* The member name of object node obj (its index), or 0 when absent (the
 * top value, index 0, is never a member). Names are compared as written
 * (escapes are not decoded: the names this package writes have none). */
size_t af_json_member(const af_json_doc *doc, size_t obj, const char *name);

/* The number at node k into *out: false when it is not a number. null
 * reads as NaN when null_is_nan (the writers write a non-finite value as
 * null). */
bool af_json_number(const af_json_doc *doc, size_t k, bool null_is_nan, double *out);

/* A whole number >= 0 that a uint64_t holds exactly (no fraction, no
 * exponent form beyond it); false otherwise. */
bool af_json_u64(const af_json_doc *doc, size_t k, uint64_t *out);

/* The string at node k, its escapes decoded (UTF-8), into buf: false when
 * it is not a string or does not fit (len bytes with its NUL). */
bool af_json_string_of(const af_json_doc *doc, size_t k, char *buf, size_t len);

/* A name of the type, for messages ("a number", "an object"). */
const char *af_json_type_name(af_json_type t);

#ifdef __cplusplus
}
#endif
#endif
