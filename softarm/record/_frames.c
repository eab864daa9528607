/* The recorder's hot path in C: one arm's block of frames as MCAP message records, byte for byte what the
   Python encoder writes (softarm/record/writer.py; docs/recording.md).

   Per frame, five records back to back, each a 31-byte header (opcode 0x05, record length, channel,
   sequence 0, log time = publish time) and its data: the mono8 foxglove.RawImage (protobuf, the bytes
   around the timestamp and pixels given), then the JSON of /arm/stretch, /arm/nodes, /arm/excitation and
   /arm/disturbance. Floats with at most nine decimals (times in s from integer ns; node positions, rounded
   to the nanometre as np.round does) are written from their integer count of nanounits, which is their
   shortest round-trip text while |value| < 1e6; the other floats (stretch, displacement) and the active
   lists come already written by orjson, one call per block, and are cut into frames here, as are the touching
   lists where the recording has obstacles (an empty buffer: no "touching" key). Returns None
   when a value is outside that range (or not finite): the caller then uses the Python encoder. */

#define PY_SSIZE_T_CLEAN
#include <Python.h>
#include <math.h>
#include <stdint.h>
#include <string.h>

#define HEADER 31
#define SAFE_NANOS 1000000000000000LL /* |k| < 1e15: k's digits are the double's shortest text */

static char *put_le(char *o, uint64_t v, int bytes)
{
    for (int i = 0; i < bytes; i++, v >>= 8)
        *o++ = (char)(v & 0xff);
    return o;
}

static char *put_varint(char *o, uint64_t v)
{
    while (v >= 0x80) {
        *o++ = (char)((v & 0x7f) | 0x80);
        v >>= 7;
    }
    *o++ = (char)v;
    return o;
}

static char *put_text(char *o, const char *s, size_t n)
{
    memcpy(o, s, n);
    return o + n;
}

static const char PAIRS[] = "00010203040506070809101112131415161718192021222324252627282930313233343536373839"
                            "40414243444546474849505152535455565758596061626364656667686970717273747576777879"
                            "8081828384858687888990919293949596979899";

/* v (< 10^width) as exactly `width` digits, zero-padded; the end. */
static char *put_digits(char *o, uint64_t v, int width)
{
    for (int i = width; i >= 2; i -= 2, v /= 100)
        memcpy(o + i - 2, PAIRS + 2 * (v % 100), 2);
    if (width % 2)
        o[0] = (char)('0' + v);
    return o + width;
}

static int digit_count(uint64_t v)
{
    int n = 1;
    while (v >= 10)
        v /= 10, n++;
    return n;
}

/* orjson's text of the double nearest k * 1e-9 (|k| < SAFE_NANOS), sign from `negative` (-0.0 included):
   fixed notation from 1e-5 on, d.ddde-N below, as orjson (ryu's layout) writes it. */
static char *put_nanos(char *o, int64_t k, int negative)
{
    uint64_t u = k < 0 ? (uint64_t)(-k) : (uint64_t)k, whole = u / 1000000000u, part = u % 1000000000u;
    int zeros = 0; /* trailing zeros of the nine decimals */
    if (negative)
        *o++ = '-';
    if (u == 0)
        return put_text(o, "0.0", 3);
    for (uint64_t p = part; p % 10 == 0 && zeros < 9; p /= 10)
        zeros++;
    if (whole) {
        o = put_digits(o, whole, digit_count(whole));
        *o++ = '.';
        return part ? put_digits(o, part, 9) - zeros : put_text(o, "0", 1);
    }
    int n = digit_count(part);
    if (n >= 5) /* 1e-5 <= value < 1 */
        return put_digits(put_text(o, "0.", 2), part, 9) - zeros;
    char sig[4];
    put_digits(sig, part, n);
    *o++ = sig[0];
    if (n - zeros > 1) {
        *o++ = '.';
        o = put_text(o, sig + 1, (size_t)(n - zeros - 1));
    }
    return o + sprintf(o, "e-%d", 10 - n);
}

/* The next bracketed row "[...]" of a JSON list of rows (no nested brackets): its inside, the cursor past it. */
static int next_row(const char **cursor, const char *end, const char **start, Py_ssize_t *length)
{
    const char *c = *cursor;
    if (c < end && (*c == ',' || *c == '['))
        c++;
    if (c >= end || *c != '[')
        return 0;
    const char *close = memchr(c, ']', (size_t)(end - c));
    if (close == NULL)
        return 0;
    *start = c + 1;
    *length = close - c - 1;
    *cursor = close + 1;
    return 1;
}

/* The next item of a flat JSON list "[a,b,...]", the cursor past it. */
static int next_item(const char **cursor, const char *end, const char **start, Py_ssize_t *length)
{
    const char *c = *cursor + 1; /* past '[' or ',' */
    const char *stop = c;
    while (stop < end && *stop != ',' && *stop != ']')
        stop++;
    if (stop >= end || stop == c)
        return 0;
    *start = c;
    *length = stop - c;
    *cursor = stop;
    return 1;
}

static char *begin_json(char *o, int64_t ns, const char *key, size_t key_length)
{
    o = put_text(o, "{\"t\":", 5);
    o = put_nanos(o, ns, ns < 0);
    return put_text(o, key, key_length);
}

static char *finish_record(char *record, char *o, int channel, int64_t ns, int64_t *size)
{
    int64_t data = o - record - HEADER;
    char *h = put_le(record, 0x05, 1);
    h = put_le(h, (uint64_t)(22 + data), 8);
    h = put_le(h, (uint64_t)channel, 2);
    h = put_le(h, 0, 4);
    h = put_le(h, (uint64_t)ns, 8);
    put_le(h, (uint64_t)ns, 8);
    *size = data;
    return o;
}

static char *put_image(char *o, int64_t ns, const Py_buffer *middle, const uint8_t *pixels, Py_ssize_t count,
                       const Py_buffer *tail)
{
    char stamp[24], *s = stamp;
    uint64_t seconds = (uint64_t)ns / 1000000000u, nanos = (uint64_t)ns % 1000000000u;
    if (seconds)
        s = put_varint(put_le(s, 0x08, 1), seconds);
    if (nanos)
        s = put_varint(put_le(s, 0x10, 1), nanos);
    *o++ = 0x0A;
    o = put_varint(o, (uint64_t)(s - stamp));
    o = put_text(o, stamp, (size_t)(s - stamp));
    o = put_text(o, middle->buf, (size_t)middle->len);
    for (Py_ssize_t i = 0; i < count; i++)
        o[i] = (char)(uint8_t)(pixels[i] * 255u);
    return put_text(o + count, tail->buf, (size_t)tail->len);
}

/* The nodes' JSON body "[[x,y],...]" or NULL when a position is outside the safe range. */
static char *put_positions(char *o, const double *p, Py_ssize_t nodes)
{
    *o++ = '[';
    for (Py_ssize_t i = 0; i < 2 * nodes; i++) {
        double scaled = rint(p[i] * 1e9); /* np.round(x, 9): x * 1e9, rint, / 1e9 */
        if (!(fabs(scaled) < (double)SAFE_NANOS))
            return NULL;
        o = put_text(o, i % 2 ? "," : (i ? ",[" : "["), i % 2 ? 1 : (i ? 2 : 1));
        o = put_nanos(o, (int64_t)scaled, signbit(scaled));
        if (i % 2)
            *o++ = ']';
    }
    *o++ = ']';
    return o;
}

static PyObject *encode(PyObject *self, PyObject *args)
{
    Py_buffer stamps, pixels, positions, stretch, displacement, active, touching, middle, tail, sizes;
    int channel[5];
    Py_ssize_t nodes;
    if (!PyArg_ParseTuple(args, "y*(iiiii)y*y*y*y*y*ny*y*y*w*", &stamps, &channel[0], &channel[1], &channel[2],
                          &channel[3], &channel[4], &middle, &tail, &pixels, &stretch, &positions, &nodes,
                          &displacement, &active, &touching, &sizes))
        return NULL;
    PyObject *result = NULL, *out = NULL;
    const int64_t *ns = stamps.buf;
    Py_ssize_t n = stamps.len / 8, hw = n ? pixels.len / n : 0;
    Py_ssize_t bound = n * (5 * HEADER + 6 * 64 + 24 + middle.len + hw + tail.len + nodes * 2 * 26 + 8)
                       + stretch.len + displacement.len + active.len + touching.len;
    if (sizes.len < n * 5 * 8 || positions.len < n * nodes * 2 * 8) {
        PyErr_SetString(PyExc_ValueError, "encode: sizes or positions too short for the block");
        goto done;
    }
    for (Py_ssize_t f = 0; f < n; f++)
        if (ns[f] < 0 || ns[f] >= SAFE_NANOS) {
            result = Py_NewRef(Py_None);
            goto done;
        }
    out = PyBytes_FromStringAndSize(NULL, bound);
    if (out == NULL)
        goto done;
    char *o = PyBytes_AS_STRING(out), *record;
    int64_t *size = sizes.buf;
    const char *rows = stretch.buf, *rows_end = rows + stretch.len, *items = displacement.buf;
    const char *items_end = items + displacement.len, *lists = active.buf, *lists_end = lists + active.len;
    const char *touches = touching.buf, *touches_end = touches + touching.len;
    const char *piece;
    Py_ssize_t length;
    for (Py_ssize_t f = 0; f < n; f++, size += 5) {
        record = o;
        o = put_image(o + HEADER, ns[f], &middle, (const uint8_t *)pixels.buf + f * hw, hw, &tail);
        o = finish_record(record, o, channel[0], ns[f], &size[0]);
        if (!next_row(&rows, rows_end, &piece, &length))
            goto malformed;
        record = o;
        o = put_text(begin_json(o + HEADER, ns[f], ",\"stretch\":[", 12), piece, (size_t)length);
        o = finish_record(record, put_text(o, "]}", 2), channel[1], ns[f], &size[1]);
        record = o;
        o = put_positions(begin_json(o + HEADER, ns[f], ",\"positions\":", 13),
                          (const double *)positions.buf + f * nodes * 2, nodes);
        if (o == NULL) {
            Py_DECREF(out);
            result = Py_NewRef(Py_None); /* the Python encoder writes this block */
            goto done;
        }
        o = finish_record(record, put_text(o, "}", 1), channel[2], ns[f], &size[2]);
        if (!next_item(&items, items_end, &piece, &length))
            goto malformed;
        record = o;
        o = put_text(begin_json(o + HEADER, ns[f], ",\"displacement\":", 16), piece, (size_t)length);
        o = finish_record(record, put_text(o, "}", 1), channel[3], ns[f], &size[3]);
        if (!next_row(&lists, lists_end, &piece, &length))
            goto malformed;
        record = o;
        o = put_text(begin_json(o + HEADER, ns[f], ",\"active\":[", 11), piece, (size_t)length);
        if (touching.len > 0) {
            if (!next_row(&touches, touches_end, &piece, &length))
                goto malformed;
            o = put_text(put_text(o, "],\"touching\":[", 14), piece, (size_t)length);
        }
        o = finish_record(record, put_text(o, "]}", 2), channel[4], ns[f], &size[4]);
    }
    if (_PyBytes_Resize(&out, o - PyBytes_AS_STRING(out)) == 0)
        result = out;
    goto done;
malformed:
    Py_DECREF(out);
    PyErr_SetString(PyExc_ValueError,
                    "encode: the stretch, displacement, active or touching JSON has fewer rows than frames");
done:
    PyBuffer_Release(&stamps), PyBuffer_Release(&middle), PyBuffer_Release(&tail), PyBuffer_Release(&pixels);
    PyBuffer_Release(&stretch), PyBuffer_Release(&positions), PyBuffer_Release(&displacement);
    PyBuffer_Release(&active), PyBuffer_Release(&touching), PyBuffer_Release(&sizes);
    return result;
}

static PyMethodDef methods[] = {
    {"encode", encode, METH_VARARGS,
     "encode(stamps, channels, image_middle, image_tail, pixels, stretch_json, positions, nodes, displacement_json, "
     "active_json, touching_json (empty: none), sizes) -> bytes | None: a block's message records (see the module's source)."},
    {NULL, NULL, 0, NULL}};

static struct PyModuleDef module = {PyModuleDef_HEAD_INIT, "_frames", NULL, -1, methods};

PyMODINIT_FUNC PyInit__frames(void) { return PyModule_Create(&module); }
