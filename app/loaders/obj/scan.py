"""The compiled half of the fast OBJ reader: two passes over the bytes, machine code by numba.

Pass one counts the rows of each table, the faces and their corners in a piece of the text (and a
quick scan says whether it holds a byte only the text checks judge, text.py); pass two writes them
straight into the whole file's tables at the offsets the counts give. A line is read byte by byte, up to its
newline (every line ends with one: the caller makes sure), with nothing allocated per line. A line
this code does not read itself, valid or not (an exponent past 1e22, a number of more than 15
digits, any error, o/g/usemtl and the like), is listed as a *record*, in file order, for the Python
side (fast.py) and the line reader.
"""

from __future__ import annotations

import numpy as np

from marraztu.loaders.obj.raw import COLOURED_V_NUMBERS, MAX_DIGITS, V_FORMS
from marraztu.model.geometry import FLOAT32_MAX
from marraztu.model.jit import has_cached_code, njit
from marraztu.model.mesh import INDEX_LIMIT

# Kinds of line, and the columns of a pass-one count.
V, VT, VN, F = 0, 1, 2, 3
LINES, CORNERS = 4, 5
COUNT_COLUMNS = 6
_NO_KEYWORD, _OTHER_KEYWORD, USEMTL_KEYWORD, MTLLIB_KEYWORD, ELEMENTS_KEYWORD = -1, -2, -3, -4, -5
# What a record is: a table or face line for the line reader, another statement, a comment that
# may be the seed's "# colour" or ZBrush's "#MRGB", or a piece's first v line with a colour after its x y z.
DEFERRED, STATEMENT, COMMENT, VERTEX_COLOURS = 0, 1, 2, 3
# Columns of a record: its kind, the line's bytes and number, the rows of v, vt and vn before it,
# the faces and corners before it, its keyword's kind, and a usemtl line's place among the piece's
# distinct ones (-1: another record, or past NAMES_PER_PIECE of them).
R_KIND, R_START, R_END, R_LINE, R_V, R_VT, R_VN, R_FACE, R_CORNER, R_KEYWORD, R_NAME = range(11)
RECORD_COLUMNS = 11
NAMES_PER_PIECE = 64  # distinct usemtl lines a piece tells apart: a model uses a few materials
# Where pass two is in a piece: the counts (as COUNT_COLUMNS, LINES being the next line's number),
# the next line's first byte, the records used, what the piece has recorded once (_STATED...), its
# mtllib lines recorded, its distinct usemtl lines, the place among them of its last usemtl line
# recorded (-1: none, or one past them), and its v lines of no v form (raw.UnformedVLines) it read:
# how many, and the first one's number (0: none). Counted, not recorded: a file may hold millions.
S_AT, S_USED, S_FLAGS, S_LIBRARIES, S_NAMES, S_LAST_NAME, S_UNFORMED, S_FIRST_UNFORMED = range(
    COUNT_COLUMNS, COUNT_COLUMNS + 8)
STATE_COLUMNS = COUNT_COLUMNS + 8
# The flags of what a piece has recorded: a statement (one says the file has some), a colour comment
# that sets the colour (later ones cannot), a v line with a colour, an l or p line (one a piece is
# enough of each).
_STATED, _COLOUR_SET, _COLOURS_SEEN, _ELEMENTS_SEEN = 1, 2, 4, 8

_NEWLINE, _HASH, _SLASH, _MINUS, _PLUS, _DOT, _ZERO, _NINE = (ord(c) for c in "\n#/-+.09")
_LETTER_V, _LETTER_T, _LETTER_N, _LETTER_F, _LOWER_CASE = ord("v"), ord("t"), ord("n"), ord("f"), 0x20
_LETTER_L, _LETTER_P = ord("l"), ord("p")
_LETTER_E, _LETTER_U, _LETTER_R, _COLO = ord("e"), ord("u"), ord("r"), np.frombuffer(b"colo", np.uint8)
# What a comment is to the colour reader (raw.ColourComment): not the seed's "# colour r g b"; one
# whose three numbers this code reads, so it sets the colour; one only the Python side can judge.
_NOT_COLOUR, _COLOUR_READ, _COLOUR_UNREAD = 0, 1, 2
_USEMTL, _MTLLIB = np.frombuffer(b"usemtl", np.uint8), np.frombuffer(b"mtllib", np.uint8)
_MRGB = np.frombuffer(b"MRGB", np.uint8)
# By a v line's count of numbers (3 to 7): whether it fits no v form (raw.V_FORMS).
_NO_V_FORM = np.ones(8, np.bool_)
_NO_V_FORM[list(V_FORMS)] = False
# Up to 1e22 powers of ten are exact doubles: mantissa and power then round once, as float() does
# (Clinger's fast path).
_POWERS_OF_TEN = np.array([10.0**k for k in range(23)])
# The bytes that only the Python side's text checks judge (marraztu.loaders.obj.text): a NUL, a CR
# (a lone one ends a line), a backslash (it may continue a line), and the first byte of a UTF-8
# no-break space. A text without them is not checked.
_TO_LOOK_AT = np.zeros(256, np.uint8)
_TO_LOOK_AT[[0, ord("\r"), ord("\\"), 0xC2]] = 1
# Each of them repeated over a word's eight bytes (holds_bytes_to_look_at), and the words' constants.
_LOW_BITS, _HIGH_BITS = np.uint64(0x0101010101010101), np.uint64(0x8080808080808080)
_NULS, _CRS, _BACKSLASHES, _C2S = (np.uint64(byte) * _LOW_BITS for byte in np.flatnonzero(_TO_LOOK_AT))
# The blanks (what bytes.split() splits on, but the newline), and the bytes that end a token: a
# blank, the newline. Looked up, not compared: one load a byte where comparing took seven, in the
# passes' innermost loops. A '#' starts a comment only where a token would start (raw.without_comment):
# inside one it is the token's, and makes it no number (-1.#IND, old Windows programs' NaN).
_BLANK = np.zeros(256, np.bool_)
_BLANK[list(b" \t\v\f\r")] = True
_ENDS_TOKEN = _BLANK.copy()
_ENDS_TOKEN[_NEWLINE] = True
_JIT = {"cache": True, "nogil": True, "error_model": "numpy"}  # cached machine code; threads run at once
# The helpers the line loops call, inlined: a call passes the array with its reference count and
# returns its tuple through memory, per number. Only these: inlining more slows the first compile.
_INLINED = dict(_JIT, inline="always")
# The passes' loops without numba's reference counts, which would cost an atomic increment and
# decrement of an array's count per number. So those loops allocate nothing, and copy no slice (a
# copy needs the counts too).
_UNCOUNTED = dict(_JIT, _nrt=False)


@njit(**_JIT)
def _byte(buf: np.ndarray, at: int) -> int:
    """buf[at], by an unsigned index: numba checks every signed one for a negative value to count
    from the end, a branch on every byte the passes read."""
    return buf[np.uint64(at)]


@njit(**_JIT)
def _is_blank(byte: int) -> bool:
    return _BLANK[byte]


@njit(**_JIT)
def _ends_token(byte: int) -> bool:
    return _ENDS_TOKEN[byte]


@njit(**_JIT)
def _is_digit(byte: int) -> bool:
    return _ZERO <= byte <= _NINE


@njit(**_INLINED)
def _skip_blanks(buf: np.ndarray, at: int) -> int:
    while _is_blank(_byte(buf, at)):
        at += 1
    return at


@njit(**_INLINED)
def _token_end(buf: np.ndarray, at: int) -> int:
    while not _ends_token(_byte(buf, at)):
        at += 1
    return at


@njit(**_INLINED)
def line_end(buf: np.ndarray, at: int) -> int:
    while _byte(buf, at) != _NEWLINE:
        at += 1
    return at


@njit(**_INLINED)
def _keyword(buf: np.ndarray, start: int) -> tuple[int, int]:
    """The line's kind (V, VT, VN, F, or _NO_KEYWORD, _OTHER_KEYWORD) and where its keyword ends."""
    at = _skip_blanks(buf, start)
    if _byte(buf, at) == _HASH:  # a comment line
        return _NO_KEYWORD, at
    stop = _token_end(buf, at)
    length = stop - at
    if length == 0:
        return _NO_KEYWORD, stop
    if length == 1 and _byte(buf, at) == _LETTER_V:
        return V, stop
    if length == 1 and _byte(buf, at) == _LETTER_F:
        return F, stop
    if length == 2 and _byte(buf, at) == _LETTER_V and _byte(buf, at + 1) == _LETTER_T:
        return VT, stop
    if length == 2 and _byte(buf, at) == _LETTER_V and _byte(buf, at + 1) == _LETTER_N:
        return VN, stop
    return _OTHER_KEYWORD, stop


@njit(**_JIT)
def _tokens(buf: np.ndarray, at: int) -> tuple[int, int]:
    """Whitespace-separated tokens before any '#' (a face line's corners), and where they end."""
    count = 0
    while True:
        at = _skip_blanks(buf, at)
        if _byte(buf, at) == _NEWLINE or _byte(buf, at) == _HASH:
            return count, at
        count += 1
        at = _token_end(buf, at)


@njit(**_UNCOUNTED)
def count_piece(buf: np.ndarray, low: int, high: int, counts: np.ndarray) -> None:
    """Rows of v, vt and vn, faces, lines and corners in buf[low:high], whole lines, added to `counts`
    (COUNT_COLUMNS)."""
    start = low
    while start < high:
        if _byte(buf, start) == _NEWLINE:  # an empty line, in a loop of its own: a file of them must be cheap
            counts[LINES] += 1
            start += 1
            continue
        kind, after = _keyword(buf, start)
        if kind >= 0:
            counts[kind] += 1
        if kind == F:
            corners, after = _tokens(buf, after)
            counts[CORNERS] += corners
        counts[LINES] += 1
        start = line_end(buf, after) + 1


@njit(**_JIT)
def holds_bytes_to_look_at(buf: np.ndarray, low: int, high: int) -> bool:
    """Whether buf[low:high] holds a byte only the text checks judge (_TO_LOOK_AT): eight bytes at a
    time, as aligned words, where a word holds byte b if (word ^ bbbbbbbb) has a zero byte."""
    first = min(high, low + (-(buf.ctypes.data + low)) % 8)
    last = first + (high - first) // 8 * 8
    found = 0
    for at in range(low, first):
        found |= _TO_LOOK_AT[_byte(buf, at)]
    for at in range(last, high):
        found |= _TO_LOOK_AT[_byte(buf, at)]
    words, zeros = buf[first:last].view(np.uint64), np.uint64(0)
    for at in range(words.shape[0]):  # indexed, not iterated: LLVM vectorizes this loop
        word = words[at]
        zeros |= _zero_bytes(word ^ _NULS) | _zero_bytes(word ^ _CRS) | _zero_bytes(word ^ _BACKSLASHES) \
            | _zero_bytes(word ^ _C2S)
    return found != 0 or zeros != 0


@njit(**_JIT)
def _zero_bytes(word: np.uint64) -> np.uint64:
    """Not zero if and only if a byte of the word is zero: subtracting 1 sets a byte's top bit only
    where it was 0 or above 0x80, ~word clears it for the latter, and only a zero byte borrows."""
    return (word - _LOW_BITS) & ~word & _HIGH_BITS


@njit(**_INLINED)
def _number(buf: np.ndarray, at: int) -> tuple[float, int, bool]:
    """The decimal number at `at` (float()'s syntax), where it ends, and whether it was read: False for
    anything else, and for what needs more than a double's exact range (the line reader reads it)."""
    negative = _byte(buf, at) == _MINUS
    if negative or _byte(buf, at) == _PLUS:
        at += 1
    mantissa, digits, exponent, seen = 0, 0, 0, False
    while _is_digit(_byte(buf, at)):
        mantissa, seen = mantissa * 10 + (_byte(buf, at) - _ZERO), True
        digits += mantissa > 0  # leading zeros are not significant
        at += 1
    if _byte(buf, at) == _DOT:
        at += 1
        while _is_digit(_byte(buf, at)):
            mantissa, seen = mantissa * 10 + (_byte(buf, at) - _ZERO), True
            digits += mantissa > 0
            exponent -= 1
            at += 1
    if not seen or digits > MAX_DIGITS:  # more significant digits than a double holds exactly
        return 0.0, at, False
    if _byte(buf, at) | _LOWER_CASE == _LETTER_E:
        at += 1
        sign = -1 if _byte(buf, at) == _MINUS else 1
        if _byte(buf, at) == _MINUS or _byte(buf, at) == _PLUS:
            at += 1
        if not _is_digit(_byte(buf, at)):
            return 0.0, at, False
        power = 0
        while _is_digit(_byte(buf, at)):
            power = min(power * 10 + (_byte(buf, at) - _ZERO), 10_000)  # bounded: 1e99999999999 must not wrap
            at += 1
        exponent += sign * power
    if not _ends_token(_byte(buf, at)):
        return 0.0, at, False
    if mantissa == 0:
        value = 0.0
    elif 0 <= exponent <= 22:
        value = mantissa * _POWERS_OF_TEN[exponent]
    elif -22 <= exponent < 0:
        value = mantissa / _POWERS_OF_TEN[-exponent]
    else:
        return 0.0, at, False
    if value > FLOAT32_MAX:
        return 0.0, at, False
    return (-value if negative else value), at, True


@njit(**_INLINED)
def _numbers(buf: np.ndarray, at: int, table: np.ndarray, row: int, fewest: int, most: int) -> tuple[int, int]:
    """A v, vt or vn line's numbers, the first table.shape[1] of them into table[row]: how many it
    holds, or -1 where they were not read (the line reader reads the line), and where reading stopped.
    The row is written by index: a view of it per line costs more than the line's numbers."""
    count, width = 0, table.shape[1]
    while True:
        at = _skip_blanks(buf, at)
        if _byte(buf, at) == _NEWLINE or _byte(buf, at) == _HASH:
            if count < fewest:
                return -1, at
            for column in range(count, width):  # `vt u`: v is 0, as the format says
                table[row, column] = 0.0
            return count, at
        if count == most:
            return -1, at
        value, at, ok = _number(buf, at)
        if not ok:
            return -1, at
        if count < width:
            table[row, count] = value
        count += 1


@njit(**_INLINED)
def _index(buf: np.ndarray, at: int, defined: int) -> tuple[int, int]:
    """A face index made 0-based (a relative one counted back from `defined`) and where it ends;
    -1 when it is not one this code reads (0, past a 32-bit index, reaching before the first, no digits)."""
    negative = _byte(buf, at) == _MINUS
    if negative:
        at += 1
    value, digits = 0, 0
    while _is_digit(_byte(buf, at)):
        value = value * 10 + (_byte(buf, at) - _ZERO)
        digits += 1
        at += 1
    if digits == 0 or digits > MAX_DIGITS or value == 0 or value > INDEX_LIMIT:
        return -1, at
    if negative:
        return (defined - value if defined >= value else -1), at
    return value - 1, at


@njit(**_INLINED)
def _face(buf: np.ndarray, at: int, defined: np.ndarray, vertex: np.ndarray, texcoord: np.ndarray,
          normal: np.ndarray, first: int) -> tuple[int, int]:
    """A face line's 0-based v, vt, vn per corner from `first` on (-1: no vt or vn): how many corners,
    or -1 when the line is the line reader's, and where reading stopped. Every corner must have the
    first one's format; positive indices may point forward (checked once the file is read).

    The loop leaves only at the line's end: a bad corner is noted and read past, because a loop that
    can leave at one compiles to much slower code. Each turn takes one token, so a bad line fills no
    more slots than pass one counted for it (the line reader fills them again)."""
    count, shape, bad = 0, -1, False
    while True:
        at = _skip_blanks(buf, at)
        if _byte(buf, at) == _NEWLINE or _byte(buf, at) == _HASH:
            return (count if count >= 3 and not bad else -1), at
        v, at = _index(buf, at, defined[V])
        t = n = -1
        corner_shape = 0
        if _byte(buf, at) == _SLASH:
            at += 1
            if _byte(buf, at) != _SLASH:
                t, at = _index(buf, at, defined[VT])
                corner_shape |= 1
            if _byte(buf, at) == _SLASH:
                n, at = _index(buf, at + 1, defined[VN])
                corner_shape |= 2
        bad |= ((v < 0) | ((corner_shape & 1) != 0) & (t < 0) | ((corner_shape & 2) != 0) & (n < 0)
                | (not _ends_token(_byte(buf, at))) | (shape >= 0) & (corner_shape != shape))
        at = _token_end(buf, at)  # past what is left of a bad token: each turn moves on
        corner = first + count
        vertex[corner], texcoord[corner], normal[corner] = v, t, n
        shape = corner_shape
        count += 1


@njit(**_JIT)
def _colour_comment(buf: np.ndarray, at: int) -> int:
    """What the comment whose '#' is at `at` is to the colour reader: raw.COLOUR_COMMENT's shape ("colour"
    or "color", then exactly three words) is checked here; its words are _COLOUR_READ when each is a
    number _number reads whole, which Python's float() reads too."""
    at = _skip_blanks(buf, at + 1)
    if not _word_at(buf, at, _COLO):
        return _NOT_COLOUR
    at += 4 + (_byte(buf, at + 4) == _LETTER_U)
    if _byte(buf, at) != _LETTER_R or not _is_blank(_byte(buf, at + 1)):
        return _NOT_COLOUR
    at, read = at + 1, True
    for _ in range(3):
        at = _skip_blanks(buf, at)
        if _byte(buf, at) == _NEWLINE:
            return _NOT_COLOUR
        end = at
        while not _is_blank(_byte(buf, end)) and _byte(buf, end) != _NEWLINE:  # a word: '#' and all, as \S+ reads it
            end += 1
        _, stop, ok = _number(buf, at)
        read = read and ok and stop == end
        at = end
    if _byte(buf, _skip_blanks(buf, at)) != _NEWLINE:
        return _NOT_COLOUR
    return _COLOUR_READ if read else _COLOUR_UNREAD


@njit(**_JIT)
def _word_at(buf: np.ndarray, at: int, word: np.ndarray) -> bool:
    for offset in range(word.shape[0]):  # buf ends with a newline, which no word holds: never past the end
        if _byte(buf, at + offset) != word[offset]:
            return False
    return True


@njit(**_JIT)
def _place_among(buf: np.ndarray, start: int, end: int, names: np.ndarray, named: int) -> int:
    """Where buf[start:end] is among the first `named` lines `names` holds; `named` where it is not."""
    for place in range(named):
        if _same_bytes(buf, start, end, names[place, 0], names[place, 1]):
            return place
    return named


@njit(**_JIT)
def _named_part(buf: np.ndarray, start: int, end: int) -> tuple[int, int]:
    """The bounds of what the statement buf[start:end] names (raw.statement's rest): after its keyword and
    blanks, up to a '#' or the line's end, without the blanks that end it."""
    at = _skip_blanks(buf, _token_end(buf, _skip_blanks(buf, start)))
    stop = at
    while stop < end and not (_byte(buf, stop) == _HASH and (stop == at or _is_blank(_byte(buf, stop - 1)))):
        stop += 1
    while stop > at and _is_blank(_byte(buf, stop - 1)):
        stop -= 1
    return at, stop


@njit(**_JIT)
def _same_bytes(buf: np.ndarray, start: int, end: int, other_start: int, other_end: int) -> bool:
    if end - start != other_end - other_start:
        return False
    for offset in range(end - start):
        if _byte(buf, start + offset) != _byte(buf, other_start + offset):
            return False
    return True


@njit(**_JIT)
def _statement_kind(buf: np.ndarray, start: int) -> int:
    """USEMTL_KEYWORD, MTLLIB_KEYWORD (the only statements the loader reads), ELEMENTS_KEYWORD (l and p,
    which it says it does not draw), or _OTHER_KEYWORD."""
    at = _skip_blanks(buf, start)
    if _token_end(buf, at) - at == 1 and (_byte(buf, at) == _LETTER_L or _byte(buf, at) == _LETTER_P):
        return ELEMENTS_KEYWORD
    if _token_end(buf, at) - at == 6:
        if _word_at(buf, at, _USEMTL):
            return USEMTL_KEYWORD
        if _word_at(buf, at, _MTLLIB):
            return MTLLIB_KEYWORD
    return _OTHER_KEYWORD


@njit(**_UNCOUNTED)
def read_piece(buf: np.ndarray, high: int, state: np.ndarray, records: np.ndarray, names: np.ndarray,
               libraries_named: np.ndarray, positions: np.ndarray, texcoords: np.ndarray, normals: np.ndarray,
               vertex: np.ndarray, texcoord: np.ndarray, normal: np.ndarray, face_start: np.ndarray) -> None:
    """Pass two over a piece, up to `high`: its rows, corners and face ends into the whole file's
    tables, and its records into `records`. `state` says where it is (STATE_COLUMNS): the counts so
    far in the whole file, the next line, and the records used. `names`, (NAMES_PER_PIECE, 2): the
    bytes of the piece's distinct usemtl lines, each record's R_NAME the place of its own;
    `libraries_named`, the bounds of the names of its first distinct mtllib lines. It returns
    once the piece is read or `records` is full, to be called again with more room: growing them
    here would cost every line."""
    defined = state[:3]  # the rows of v, vt and vn so far, counted in place
    face, corner, line = state[F], state[CORNERS], state[LINES]
    start, used, flags, libraries = state[S_AT], state[S_USED], state[S_FLAGS], state[S_LIBRARIES]
    named, last_name = state[S_NAMES], state[S_LAST_NAME]
    unformed, first_unformed = state[S_UNFORMED], state[S_FIRST_UNFORMED]
    while start < high and used < records.shape[0]:
        if _byte(buf, start) == _NEWLINE:
            line += 1
            start += 1
            continue
        kind, at = _keyword(buf, start)
        record, corners, read, name = -1, 0, True, -1
        if kind == V:
            numbers, at = _numbers(buf, at, positions, defined[V], 3, 7)
            read = numbers >= 0
            if numbers >= COLOURED_V_NUMBERS and not flags & _COLOURS_SEEN:
                record, flags = VERTEX_COLOURS, flags | _COLOURS_SEEN
            if read and _NO_V_FORM[numbers]:
                unformed += 1
                first_unformed = first_unformed or line
        elif kind == VT:
            numbers, at = _numbers(buf, at, texcoords, defined[VT], 1, 3)
            read = numbers >= 0
        elif kind == VN:
            numbers, at = _numbers(buf, at, normals, defined[VN], 3, 3)
            read = numbers >= 0
        elif kind == F:
            corners, stop = _face(buf, at, defined, vertex, texcoord, normal, corner)
            if corners < 0:
                read, corners = False, _tokens(buf, at)[0]  # its slots, as pass one counted them
            at = stop
        elif kind == _OTHER_KEYWORD:
            kind = _statement_kind(buf, start)
            # usemtl and mtllib are read; of the rest (g, o, s...) one says the file has statements
            record = STATEMENT if not flags & _STATED or kind != _OTHER_KEYWORD else -1
            if kind == ELEMENTS_KEYWORD and flags & _ELEMENTS_SEEN:  # one a piece says the file has some
                record = -1
            flags |= _STATED | (_ELEMENTS_SEEN if kind == ELEMENTS_KEYWORD else 0)
        end = line_end(buf, at)
        if kind == MTLLIB_KEYWORD:  # a piece's first distinct names hold the file's first (raw.with_library)
            low, stop = _named_part(buf, start, end)
            if libraries < libraries_named.shape[0] and _place_among(buf, low, stop, libraries_named,
                                                                     libraries) == libraries:
                libraries_named[libraries, 0], libraries_named[libraries, 1] = low, stop
                libraries += 1
                record = STATEMENT
            else:
                record = -1
        elif kind == USEMTL_KEYWORD:
            name = _place_among(buf, start, end, names, named)
            if name == named and named < names.shape[0]:  # a line the piece had not shown: it joins them
                names[named, 0], names[named, 1] = start, end
                named += 1
            elif name == named:
                name = -1
            if name >= 0 and name == last_name:
                record = -1  # the material its faces use already: a usemtl before every face is one run
        if not read:
            record = DEFERRED
        elif kind == _NO_KEYWORD and _byte(buf, at) == _HASH:
            if _word_at(buf, at + 1, _MRGB):  # ZBrush's polypaint: every line counts (raw.Polypaint)
                record = COMMENT
            elif not flags & _COLOUR_SET:
                shape = _colour_comment(buf, at)
                if shape != _NOT_COLOUR:
                    record = COMMENT
                    flags |= _COLOUR_SET if shape == _COLOUR_READ else 0
        if record >= 0 and kind == USEMTL_KEYWORD:
            if used > 0 and records[used - 1, R_KEYWORD] == USEMTL_KEYWORD and records[used - 1, R_FACE] == face:
                used -= 1  # a usemtl no face followed: this one takes its place (as raw.MaterialRuns.add does)
            last_name = name
        if record >= 0:
            row = records[used]
            row[R_KIND], row[R_START], row[R_END], row[R_LINE], row[R_KEYWORD] = record, start, end, line, kind
            row[R_V], row[R_VT], row[R_VN] = defined[V], defined[VT], defined[VN]
            row[R_FACE], row[R_CORNER], row[R_NAME] = face, corner, name
            used += 1
        if kind == F:
            corner += corners
            face += 1
            face_start[face] = corner
        elif kind >= 0:
            defined[kind] += 1
        line += 1
        start = end + 1
    state[F], state[CORNERS], state[LINES] = face, corner, line
    state[S_AT], state[S_USED], state[S_FLAGS], state[S_LIBRARIES] = start, used, flags, libraries
    state[S_NAMES], state[S_LAST_NAME] = named, last_name
    state[S_UNFORMED], state[S_FIRST_UNFORMED] = unformed, first_unformed


@njit(**_UNCOUNTED)
def read_vertex_colours(buf: np.ndarray, low: int, high: int, first_row: int, colours: np.ndarray,
                        numbers_read: np.ndarray) -> None:
    """A third pass over buf[low:high], for files with `v x y z r g b` lines: each v line's 4th to 6th
    numbers into its row of `colours` from `first_row` on; rows of lines with fewer, or of lines this
    code leaves to the line reader, are left as they are. `numbers_read`, (1, 7), is this call's own
    room for a line's numbers."""
    row, start = first_row, low
    while start < high:
        if _byte(buf, start) == _NEWLINE:
            start += 1
            continue
        kind, at = _keyword(buf, start)
        if kind == V:
            numbers, at = _numbers(buf, at, numbers_read, 0, 3, 7)
            if numbers >= COLOURED_V_NUMBERS:
                for column in range(3):
                    colours[row, column] = numbers_read[0, 3 + column]
            row += 1
        start = line_end(buf, at) + 1


def machine_code_cached() -> bool | None:
    """Whether numba's cache holds the passes' machine code (False: the first file compiles them, for
    seconds); None where it cannot be asked."""
    found = [has_cached_code(function) for function in (count_piece, holds_bytes_to_look_at, read_piece, line_end)]
    return None if None in found else all(found)


@njit(**_JIT)
def line_of_face(buf: np.ndarray, face: int) -> int:
    """The line number of the file's face line number `face` (0-based): only for an error's message."""
    start, line, seen = 0, 1, 0
    while start < buf.shape[0]:
        kind, after = _keyword(buf, start)
        if kind == F:
            if seen == face:
                return line
            seen += 1
        line += 1
        start = line_end(buf, after) + 1
    return line
