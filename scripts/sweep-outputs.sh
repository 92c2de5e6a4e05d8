#!/usr/bin/env bash
# sweep-outputs.sh: a sweep of lumis's outputs for data loss and silent wrong output.
#
#   scripts/sweep-outputs.sh [path/to/lumis]        (default build/lumis)
#
# Every case runs in a fresh folder under a mktemp folder: its files are made, their state
# (type, link target, SHA-256, mode) is recorded, one lumis command runs (under timeout),
# and the state is compared.  A file that existed before and changed or vanished without
# being an output the case expects is a FAIL, as is a hidden temporary (.NAME.XXXXXX) or
# a luminaire staging folder (*.images.new-*, *.images.old-*) left behind, an output that
# silently is not what was asked (checked per case), or a refusal expected and not made.
# WARN marks behaviour worth a look that loses nothing (a refusal of a valid request, an
# option that silently loses to another, a block on a FIFO without a reader, a widened
# file mode).  One line per case; exit 1 when any case FAILs.
#
# Interrupt cases are of two kinds: timed (poll until the temporary file appears, then
# signal) and injected (an LD_PRELOAD shim raises the signal right after mkstemp, mkdtemp or
# rename returns, to hit the windows a timed signal hits only sometimes).  The shim needs a
# C compiler; without one those cases are SKIPped.
set -u
LUMIS=${1:-build/lumis}
LUMIS=$(realpath "$LUMIS") || exit 2
[ -x "$LUMIS" ] || { echo "no lumis binary at $LUMIS" >&2; exit 2; }
export L=$LUMIS
T=$(mktemp -d "${TMPDIR:-/tmp}/sweep-outputs.XXXXXX") || exit 2
export T
LOGS=$T/logs
mkdir -p "$LOGS"
KEEP=${SWEEP_KEEP:-0} # SWEEP_KEEP=1 keeps $T for inspection
MOUNTED=0
cleanup() {
    cd / && [ "$MOUNTED" = 1 ] && umount "$T/fullfs"
    [ "$KEEP" = 1 ] && echo "kept $T" || rm -rf "$T"
}
trap cleanup EXIT
export LC_ALL=C
export OMP_NUM_THREADS=2
START=$(date +%s)

N=0 NPASS=0 NFAIL=0 NWARN=0 NSKIP=0
CASE="" CDIR="" FAILS=() WARNS=() NOTES=() CMD="" RC=0
FAIL_LINES=()

# ---- framework ---------------------------------------------------------------------------

begin() { # begin NAME: a fresh, empty case folder, made the working directory
    N=$((N + 1))
    CASE=$1
    CDIR=$T/c$(printf %03d $N)
    mkdir -p "$CDIR"
    cd "$CDIR" || exit 2
    FAILS=() WARNS=() NOTES=() CMD="" RC=0
}

state() { # every entry under . : path, type, link target, short SHA-256, mode
    find . -mindepth 1 -printf '%P\t%y\t%l\t%m\n' | sort | while IFS=$'\t' read -r p y l m; do
        h=-
        [ "$y" = f ] && h=$(sha256sum <"$p" | cut -c1-16)
        printf '%s\t%s\t%s\t%s\t%s\n' "$p" "$y" "$l" "$h" "$m"
    done
}

snap() { state >"$LOGS/$N.before"; }

# run EXPECT 'shell command': EXPECT is ok (exit 0), fail (non-zero), usage (exit 2) or any
run() {
    local expect=$1
    CMD=$2
    echo "$CMD" >"$LOGS/$N.cmd"
    timeout 20 bash -c "$CMD" >"$LOGS/$N.out" 2>"$LOGS/$N.err"
    RC=$?
    expect_rc "$expect"
}

expect_rc() {
    local expect=$1
    if [ "$RC" = 124 ]; then
        warn "blocked: killed by timeout"
        return
    fi
    case $expect in
    ok) [ "$RC" = 0 ] || warn "exit $RC, expected success ($(head -c 160 "$LOGS/$N.err" | tr '\n' ' '))" ;;
    fail) [ "$RC" != 0 ] || fail "exit 0, expected an error" ;;
    usage)
        if [ "$RC" = 0 ]; then
            fail "exit 0, expected a refusal"
        elif [ "$RC" != 2 ]; then
            note "refused with exit $RC, not 2"
        fi
        ;;
    esac
}

fail() { FAILS+=("$1"); }
warn() { WARNS+=("$1"); }
note() { NOTES+=("$1"); }
stderr_says() { grep -qiE "$1" "$LOGS/$N.err"; }

# end [ALLOWED...]: compare the state with snap's; ALLOWED names paths that may change or
# appear (a trailing /* allows a folder's contents)
end() {
    local allowed=("$@")
    state >"$LOGS/$N.after"
    local kind p rest
    while IFS=$'\t' read -r kind p rest; do
        local ok=0 a
        for a in "${allowed[@]}"; do
            if [ "$p" = "$a" ] || { [ "${a%/\*}" != "$a" ] && [[ $p == "${a%/\*}"/* ]]; }; then ok=1; fi
        done
        case $kind in
        removed) [ $ok = 1 ] || fail "input removed: $p" ;;
        changed)
            if [ $ok = 1 ]; then
                # the same content and type with another mode is a widened or narrowed file
                local b0 a0
                b0=$(awk -F'\t' -v p="$p" '$1==p{print $2"\t"$3"\t"$5}' "$LOGS/$N.before")
                a0=$(awk -F'\t' -v p="$p" '$1==p{print $2"\t"$3"\t"$5}' "$LOGS/$N.after")
                if [ "$(cut -f1 <<<"$b0")" = f ] && [ "$(cut -f3 <<<"$b0")" != "$(cut -f3 <<<"$a0")" ]; then
                    warn "mode of $p changed $(cut -f3 <<<"$b0") -> $(cut -f3 <<<"$a0")"
                fi
                if [ "$(cut -f1 <<<"$b0")" = l ] && [ "$(cut -f1 <<<"$a0")" != l ]; then
                    fail "symbolic link $p replaced by a $(cut -f1 <<<"$a0") (its target $(cut -f2 <<<"$b0") not written)"
                fi
            else
                fail "input changed: $p ($rest)"
            fi
            ;;
        new)
            local base=${p##*/}
            if [[ $base =~ ^\..+\.[A-Za-z0-9]{6}$ ]]; then
                fail "temporary left: $p"
            elif [[ $p =~ \.images\.(new|old)-[A-Za-z0-9]{6}$ ]]; then
                fail "staging folder left: $p ($(find "$p" -mindepth 1 | wc -l) entries)"
            fi
            ;;
        esac
    done < <(awk -F'\t' 'NR==FNR{b[$1]=$0; next} {a[$1]=$0}
        END{for(p in b){ if(!(p in a)) print "removed\t"p"\t-"; else if(a[p]!=b[p]){split(b[p],x,"\t");split(a[p],y,"\t"); print "changed\t"p"\t"x[2]"/"x[4]" -> "y[2]"/"y[4]}}
            for(p in a) if(!(p in b)) print "new\t"p"\t-"}' "$LOGS/$N.before" "$LOGS/$N.after")
    [ -c /dev/full ] || fail "/dev/full is no longer a character device"
    [ -c /dev/null ] || fail "/dev/null is no longer a character device"
    for d in null:3 full:7; do # put them back, or every later step (and the machine) suffers
        [ -c /dev/${d%%:*} ] || { rm -f /dev/${d%%:*} && mknod -m 666 /dev/${d%%:*} c 1 ${d##*:}; } 2>/dev/null || true
    done
    report
}

report() {
    local verdict=PASS what=""
    if [ ${#FAILS[@]} -gt 0 ]; then
        verdict=FAIL
        what=$(printf '%s; ' "${FAILS[@]:0:4}")
        [ ${#FAILS[@]} -gt 4 ] && what="$what(and $((${#FAILS[@]} - 4)) more); "
        NFAIL=$((NFAIL + 1))
    elif [ ${#WARNS[@]} -gt 0 ]; then
        verdict=WARN
        what=$(printf '%s; ' "${WARNS[@]}")
        NWARN=$((NWARN + 1))
    else
        NPASS=$((NPASS + 1))
        [ ${#NOTES[@]} -gt 0 ] && what=$(printf '%s; ' "${NOTES[@]}")
    fi
    local line
    line=$(printf '%-4s %03d %s' "$verdict" "$N" "$CASE")
    [ -n "$what" ] && line="$line -- ${what%; }"
    [ "$verdict" != PASS ] && [ -n "$CMD" ] && line="$line   [cmd: ${CMD//\$L/lumis}]"
    echo "$line"
    [ "$verdict" = FAIL ] && FAIL_LINES+=("$line")
    cd "$T" || exit 2
}

skip() { # skip NAME WHY
    N=$((N + 1))
    NSKIP=$((NSKIP + 1))
    printf 'SKIP %03d %s -- %s\n' "$N" "$1" "$2"
}

# ---- fixtures ----------------------------------------------------------------------------

FIX=$T/fixtures
mkdir -p "$FIX"
"$L" convert sky:16x8 "$FIX/map.pfm" >/dev/null 2>&1
"$L" convert sky:16x8 "$FIX/map.exr" >/dev/null 2>&1
"$L" convert sky:16x8 "$FIX/map.hdr" >/dev/null 2>&1
"$L" convert sky:16x8 "$FIX/map.png" >/dev/null 2>&1
"$L" convert studio:16x8 "$FIX/test.pfm" >/dev/null 2>&1
"$L" luminaire create "$FIX/lum.json" --preset small >/dev/null 2>&1
cat >"$FIX/scene.json" <<'EOF'
{"camera": {"eye": [0, 0.6, 8], "look_at": [0, 0, 0], "fov_deg": 30, "width": 16, "height": 12},
 "environment": {"map": "sky:32x16"},
 "objects": [{"type": "sphere", "center": [0, 0, 0], "radius": 1,
              "material": {"type": "lambert", "albedo": [0.8, 0.8, 0.8]}}]}
EOF
cat >"$FIX/suite.json" <<'EOF'
{"name": "sweep", "maps": ["sky:32x16", "studio:32x16"], "scenes": ["spheres"],
 "methods": [{"method": "inversion"}, {"method": "alias"}],
 "budgets": [{"spp": 1}, {"spp": 2}], "reference": {"spp": 8}, "size": [24, 12]}
EOF
for f in map.pfm map.exr map.hdr map.png test.pfm lum.json scene.json suite.json; do
    [ -s "$FIX/$f" ] || { echo "could not make the fixture $f" >&2; exit 2; }
done
R="--size 16x12 --spp 1 --quiet" # a tiny render
export R
lum() { cp -r "$FIX/lum.json" "$FIX/lum.images" .; }

# a minimal uncompressed scan-line OpenEXR with the given constant FLOAT channels
mkexr() { # mkexr FILE W H NAME=VALUE...
    python3 - "$@" <<'EOF'
import struct, sys
path, w, h = sys.argv[1], int(sys.argv[2]), int(sys.argv[3])
chans = sorted((kv.split('=')[0], float(kv.split('=')[1])) for kv in sys.argv[4:])
def attr(name, typ, data): return name.encode() + b'\0' + typ.encode() + b'\0' + struct.pack('<i', len(data)) + data
cl = b''.join(n.encode() + b'\0' + struct.pack('<iB3xii', 2, 0, 1, 1) for n, _ in chans) + b'\0'
hdr = (attr('channels', 'chlist', cl) + attr('compression', 'compression', b'\0')
       + attr('dataWindow', 'box2i', struct.pack('<4i', 0, 0, w - 1, h - 1))
       + attr('displayWindow', 'box2i', struct.pack('<4i', 0, 0, w - 1, h - 1))
       + attr('lineOrder', 'lineOrder', b'\0') + attr('pixelAspectRatio', 'float', struct.pack('<f', 1))
       + attr('screenWindowCenter', 'v2f', struct.pack('<2f', 0, 0))
       + attr('screenWindowWidth', 'float', struct.pack('<f', 1)) + b'\0')
head = b'\x76\x2f\x31\x01' + struct.pack('<i', 2) + hdr
line = b''.join(struct.pack('<%df' % w, *([v] * w)) for _, v in chans)
chunk = lambda y: struct.pack('<ii', y, len(line)) + line
off = len(head) + 8 * h
table = b''.join(struct.pack('<Q', off + y * (8 + len(line))) for y in range(h))
open(path, 'wb').write(head + table + b''.join(chunk(y) for y in range(h)))
EOF
}

# every pixel of a little-endian PFM is (r, g, b)?  0 when so
pfm_is() { # pfm_is FILE R G B
    python3 - "$@" <<'EOF'
import struct, sys
d = open(sys.argv[1], 'rb').read()
parts = d.split(b'\n', 3)
w, h = map(int, parts[1].split()); scale = float(parts[2])
fmt = '<' if scale < 0 else '>'
v = struct.unpack(fmt + '%df' % (w * h * 3), parts[3][:w * h * 12])
want = [float(x) for x in sys.argv[2:5]]
sys.exit(0 if all(abs(v[i] - want[i % 3]) <= 1e-6 * max(1, abs(want[i % 3])) for i in range(len(v))) else 1)
EOF
}

# ---- the LD_PRELOAD shim that raises a signal right after a call returns -----------------

HOOK=""
if command -v cc >/dev/null 2>&1; then
    cat >"$T/hook.c" <<'EOF'
#define _GNU_SOURCE
#include <dlfcn.h>
#include <fcntl.h>
#include <signal.h>
#include <stdarg.h>
#include <sys/types.h>
#include <stdlib.h>
#include <string.h>
/* SWEEP_HOOK=mkstemp|mkdtemp|rename, SWEEP_MATCH=substring of the path (the new name for
 * rename), SWEEP_NTH=n (the n-th matching call, default 1), SWEEP_SIG=INT|TERM */
static int hit(const char *hook, const char *path)
{
    const char *h = getenv("SWEEP_HOOK"), *m = getenv("SWEEP_MATCH"), *n = getenv("SWEEP_NTH");
    if (!h || strcmp(h, hook) != 0) return 0;
    if (m && *m == '=' ? strcmp(path, m + 1) != 0 : m && !strstr(path, m)) return 0;
    static int count;
    return __atomic_add_fetch(&count, 1, __ATOMIC_SEQ_CST) == (n ? atoi(n) : 1);
}
static void fire(void)
{
    const char *s = getenv("SWEEP_SIG");
    raise(s && strcmp(s, "INT") == 0 ? SIGINT : SIGTERM);
}
int mkstemp(char *t)
{
    static int (*real)(char *);
    if (!real) real = (int (*)(char *))dlsym(RTLD_NEXT, "mkstemp");
    int fd = real(t);
    if (fd >= 0 && hit("mkstemp", t)) fire();
    return fd;
}
/* lumis makes its temporaries by open(O_CREAT | O_EXCL) on a name it registered first (the
 * signal handler must know the name before the file exists): "mkstemp" hooks that too */
static int excl_open(const char *sym, const char *path, int flags, mode_t mode)
{
    static int (*real[2])(const char *, int, ...);
    const int k = strcmp(sym, "open") != 0;
    if (!real[k]) real[k] = (int (*)(const char *, int, ...))dlsym(RTLD_NEXT, sym);
    int fd = real[k](path, flags, mode);
    if (fd >= 0 && (flags & O_CREAT) && (flags & O_EXCL) && hit("mkstemp", path)) fire();
    return fd;
}
int open(const char *path, int flags, ...)
{
    va_list ap;
    va_start(ap, flags);
    mode_t mode = (flags & O_CREAT) ? (mode_t)va_arg(ap, int) : 0;
    va_end(ap);
    return excl_open("open", path, flags, mode);
}
int open64(const char *path, int flags, ...)
{
    va_list ap;
    va_start(ap, flags);
    mode_t mode = (flags & O_CREAT) ? (mode_t)va_arg(ap, int) : 0;
    va_end(ap);
    return excl_open("open64", path, flags, mode);
}
char *mkdtemp(char *t)
{
    static char *(*real)(char *);
    if (!real) real = (char *(*)(char *))dlsym(RTLD_NEXT, "mkdtemp");
    char *r = real(t);
    if (r && hit("mkdtemp", t)) fire();
    return r;
}
int rename(const char *a, const char *b)
{
    static int (*real)(const char *, const char *);
    if (!real) real = (int (*)(const char *, const char *))dlsym(RTLD_NEXT, "rename");
    int r = real(a, b);
    if (r == 0 && hit("rename", b)) fire();
    return r;
}
EOF
    cc -shared -fPIC -O1 -o "$T/hook.so" "$T/hook.c" -ldl 2>"$LOGS/hook.err" && HOOK=$T/hook.so
fi
export HOOK

echo "# lumis output sweep: $L ($("$L" --version 2>&1)); uid $(id -u); folder $T"

# ==== 1. an output that is an input by another spelling ====================================

for spelling in "./x.pfm" "d/../x.pfm" "\$PWD/x.pfm" "/proc/self/cwd/x.pfm" "sl.pfm" "sl2.pfm" "hl.pfm" "dl/x.pfm" ".//x.pfm"; do
    begin "convert: OUT $spelling is IN x.pfm"
    cp "$FIX/map.pfm" x.pfm; mkdir d; ln -s x.pfm sl.pfm; ln -s sl.pfm sl2.pfm; ln x.pfm hl.pfm; ln -s . dl
    snap; run usage "\$L convert x.pfm $spelling"; end
done

begin "convert: IN via a symlink, OUT the file it names"
cp "$FIX/map.pfm" x.pfm; ln -s x.pfm sl.pfm
snap; run usage "\$L convert sl.pfm x.pfm"; end

begin "convert: PNG IN x.png, OUT ./x.png"
cp "$FIX/map.png" x.png
snap; run usage "\$L convert x.png ./x.png --tonemap aces"; end

begin "convert: OUT a hard link to IN under another extension (y.exr == x.pfm)"
cp "$FIX/map.pfm" x.pfm; ln x.pfm y.exr
snap; run usage "\$L convert x.pfm y.exr"; end

begin "render: -o is --env m.exr as ./d/../m.exr"
cp "$FIX/map.exr" m.exr; mkdir d
snap; run usage "\$L render --scene spheres --env m.exr $R -o ./d/../m.exr"; end

begin "render: --sidecar is --env m.pfm through a hard link"
cp "$FIX/map.pfm" m.pfm; ln m.pfm h.json
snap; run usage "\$L render --scene spheres --env m.pfm $R -o o.exr --sidecar h.json"; end

for sc in "./s.json" "d/../s.json" "sl.json" "hl.json"; do
    begin "render: --sidecar $sc is the scene file s.json"
    cp "$FIX/scene.json" s.json; mkdir d; ln -s s.json sl.json; ln s.json hl.json
    snap; run usage "\$L render s.json --spp 1 --quiet -o o.exr --sidecar $sc"; end
done

begin "render: default sidecar of -o s.exr is the scene s.json"
cp "$FIX/scene.json" s.json
snap; run usage "\$L render s.json --spp 1 --quiet -o s.exr"; end

begin "render: default sidecar of -o d/../s.exr is the scene s.json"
cp "$FIX/scene.json" s.json; mkdir d
snap; run usage "\$L render s.json --spp 1 --quiet -o d/../s.exr"; end

begin "render: -o a.exr --png a.png --sidecar a.exr (sidecar onto the EXR)"
snap; run usage "\$L render --scene spheres $R -o a.exr --png a.png --sidecar ./a.exr"; end

begin "render: --png and --sidecar the same new file (p.png)"
mkdir d; snap; run usage "\$L render --scene spheres $R -o a.exr --png p.png --sidecar d/../p.png"; end

begin "render: --png b.png a dangling symlink to -o a.exr (a new file)"
ln -s a.exr b.png
snap; run any "\$L render --scene spheres $R -o a.exr --png b.png --no-sidecar"
if [ "$RC" = 0 ]; then
    head -c 4 a.exr | od -An -tx1 | grep -q '76 2f 31 01' || fail "a.exr is not an EXR after exit 0: the PNG preview replaced the render"
fi
end a.exr b.png

begin "render: default sidecar a.json a dangling symlink to -o a.exr"
ln -s a.exr a.json
snap; run any "\$L render --scene spheres $R -o a.exr"
if [ "$RC" = 0 ]; then
    head -c 4 a.exr | od -An -tx1 | grep -q '76 2f 31 01' || fail "a.exr is not an EXR after exit 0: the JSON sidecar replaced the render"
fi
end a.exr a.json

begin "lights: --json a.gltf --gltf ./a.gltf (two outputs, one new file)"
snap; run usage "\$L lights sky:16x8 --method median-cut -k 2 --json a.gltf --gltf ./a.gltf"
stderr_says 'same|both' || note "refused, but not for naming one file twice"
end

begin "lights: --gltf g.gltf a dangling symlink to --json j.json"
ln -s j.json g.gltf
snap; run any "\$L lights sky:16x8 --method median-cut -k 2 --json j.json --gltf g.gltf"
if [ "$RC" = 0 ]; then
    grep -q '"lights"' j.json && ! grep -q '"asset"' j.json || fail "j.json holds the glTF after exit 0: --gltf replaced --json"
fi
end j.json g.gltf

begin "lights: --json is the map m.pfm via a hard link j.json"
cp "$FIX/map.pfm" m.pfm; ln m.pfm j.json
snap; run usage "\$L lights m.pfm --method median-cut -k 2 --json j.json"; end

begin "lights: --gltf is the map via a symlink"
cp "$FIX/map.exr" m.exr; ln -s m.exr g.gltf
snap; run usage "\$L lights m.exr --method median-cut -k 2 --gltf g.gltf"; end

begin "lights: --png is the PNG map as ./m.png"
cp "$FIX/map.png" m.png
snap; run fail "\$L lights m.png --method median-cut -k 2 --png ./m.png"; end

begin "lights: --png and --json the same existing file via a hard link"
echo old >p.png; ln p.png j.json
snap; run usage "\$L lights sky:16x8 --method median-cut -k 2 --png p.png --json j.json"; end

for spec in "--diff ./r.pfm" "--diff sl.pfm" "--diff hl.pfm" "--diff d/../t.pfm" "--map rp.png" "--map d/../rp.png"; do
    begin "compare: $spec is an input"
    cp "$FIX/map.pfm" r.pfm; cp "$FIX/test.pfm" t.pfm; cp "$FIX/map.png" rp.png; mkdir d
    ln -s r.pfm sl.pfm; ln r.pfm hl.pfm
    snap
    if [[ $spec == *rp.png ]]; then run usage "\$L compare rp.png t.pfm $spec"; else run usage "\$L compare r.pfm t.pfm $spec"; fi
    end
done

begin "compare: --map m.png --diff d/../m.png (one new file twice)"
cp "$FIX/map.pfm" r.pfm; cp "$FIX/test.pfm" t.pfm; mkdir d
snap; run usage "\$L compare r.pfm t.pfm --map m.png --diff d/../m.png"; end

shares() { # two shares of one render (lumis render --passes), with their sidecars
    "$L" render --scene spheres --size 8x6 --spp 2 --passes 0/2 --quiet -o s0.exr >/dev/null 2>&1
    "$L" render --scene spheres --size 8x6 --spp 2 --passes 1/2 --quiet -o s1.exr >/dev/null 2>&1
}
# (-o s0.pfm and -o s1.hdr: their default sidecars are the shares' s0.json and s1.json)
for spec in "-o ./s0.exr" "-o d/../s1.exr" "-o hl.exr" "-o sl.exr" "-o s0.pfm" "-o s1.hdr"; do
    begin "merge: $spec onto a share or its sidecar"
    shares; mkdir d; ln s0.exr hl.exr; ln -s s1.exr sl.exr
    snap; run usage "\$L merge s0.exr s1.exr $spec"; end
done

begin "luminaire render: default sidecar of -o lum.exr is the manifest"
lum; snap; run usage "\$L luminaire render lum.json $R -o lum.exr"; end

begin "luminaire render: -o an image of the luminaire via d/../lum.images/"
lum; mkdir d; snap; run usage "\$L luminaire render lum.json $R -o d/../lum.images/a000_b000.exr"; end

begin "luminaire render: -o a hard link to one of its images"
lum; ln lum.images/a001_b000.exr h.exr; snap; run usage "\$L luminaire render lum.json $R -o h.exr"; end

begin "luminaire render: --sidecar an image of the luminaire"
lum; snap; run usage "\$L luminaire render lum.json $R -o o.exr --sidecar lum.images/a002_b001.exr"; end

begin "render: scene file with a luminaire; -o one of its images via a symlinked folder"
lum; ln -s lum.images li
cat >s.json <<'EOF'
{"camera": {"eye": [0, 1, 4], "look_at": [0, 0, 0], "fov_deg": 40, "width": 16, "height": 12},
 "objects": [{"type": "plane", "point": [0, 0, 0], "normal": [0, 1, 0], "size": 10,
              "material": {"type": "lambert", "albedo": [0.5, 0.5, 0.5]}}],
 "luminaires": [{"file": "lum.json", "transform": {"translate": [0, 1, 0]}}]}
EOF
snap; run fail "\$L render s.json --spp 1 --quiet -o li/a000_b001.exr"; end

begin "luminaire create: OUT a symlink to another folder's luminaire manifest"
mkdir a b; (cd a && lum); ln -s ../a/lum.json b/link.json
snap; run any "\$L luminaire create b/link.json --preset small"
if [ "$RC" = 0 ]; then
    "$L" luminaire info a/lum.json >/dev/null 2>"$LOGS/$N.info" ||
        fail "a/lum.json no longer loads (it names $(grep -m1 -o '"[^"]*images/[^"]*"' a/lum.json), not beside it; a/lum.images orphaned)"
fi
end a/lum.json 'b/*'

begin "luminaire create: over a luminaire whose images folder holds a user file"
lum; echo "my notes" >lum.images/notes.txt
snap; run ok "\$L luminaire create lum.json --preset small --format pfm"
[ -f lum.images/notes.txt ] || fail "lum.images/notes.txt moved away silently (now $(ls -d lum.images.old-*/notes.txt 2>/dev/null || echo gone))"
end lum.json 'lum.images/*' lum.images

begin "luminaire create: images folder mode after create"
snap; run ok "\$L luminaire create l.json --preset small"
m=$(stat -c %a l.images 2>/dev/null); [ "$m" = 700 ] && warn "l.images made with mode 700 (private; files in it are 644)"
end 'l.images/*' l.images l.json

begin "luminaire create: OUT.images is a symlink to another luminaire's folder"
mkdir a; (cd a && lum); ln -s a/lum.images x.images
snap; run fail "\$L luminaire create x.json --preset small"; end

begin "bench: the suite is DIR/results.json and --out DIR"
mkdir o; cp "$FIX/suite.json" o/results.json
snap; run any "\$L bench o/results.json --out o --threads 1"
end 'o/refs/*' 'o/renders/*' 'o/results/*' 'o/previews/*' o/refs o/renders o/results o/previews o/results.csv o/results.md o/index.html o/flip-legend.png 'o/convergence-*' o/convergence-spheres.svg

begin "bench: --out ./s.json is the suite"
cp "$FIX/suite.json" s.json
snap; run usage "\$L bench s.json --out ./s.json"; end

begin "bench: --out a symlink to the suite"
cp "$FIX/suite.json" s.json; ln -s s.json o
snap; run usage "\$L bench s.json --out o"; end

begin "bench: --merge DIR into the same DIR"
cp "$FIX/suite.json" s.json
"$L" bench s.json --out o --threads 1 >/dev/null 2>&1
snap; run any "\$L bench s.json --out o --merge o --threads 1"
end o/results.csv o/results.json o/results.md o/index.html o/convergence-spheres.svg o/convergence-spp.svg o/flip-legend.png

begin "bench --slurm: a job script that links to the suite"
cp "$FIX/suite.json" s.json; mkdir -p o/slurm; ln -s ../../s.json o/slurm/items.sbatch
snap; run usage "\$L bench s.json --out o --slurm --no-submit"; end

begin "info: --svg onto the photometric file through d/../"
printf 'IESNA:LM-63-2002\nTILT=NONE\n1 1000 1 2 1 1 2 0 0 0\n1 1 0\n0 90\n0\n100 0\n' >f.ies; mkdir d
snap; run usage "\$L info f.ies --svg d/../f.ies"; end

begin "render: --fixture's file as the sidecar of -o f.exr"
printf 'IESNA:LM-63-2002\nTILT=NONE\n1 1000 1 2 1 1 2 0 0 0\n1 1 0\n0 90\n0\n100 0\n' >f.ies
cp f.ies f.json
snap; run usage "\$L render --scene spheres $R --fixture f.json --fixture-at 0,2,0 -o f.exr"; end

begin "sample: stdout appended to the input map (>> m.pfm)"
cp "$FIX/map.pfm" m.pfm
snap; run any "\$L sample m.pfm --method inversion -n 2 >> m.pfm"
[ "$RC" = 0 ] && warn "the map m.pfm grew by $(($(stat -c %s m.pfm) - $(stat -c %s "$FIX/map.pfm"))) bytes (stdout is the input; not detected, and the map still loads)"
end m.pfm

# ==== 2. stdout as an output file =========================================================

begin "lights: --json /dev/stdout through a pipe"
snap; run ok "\$L lights sky:16x8 --method median-cut -k 2 --json /dev/stdout | cat > \$T/logs/$N.pipe"
grep -q '"lights"' "$LOGS/$N.pipe" && grep -q 'light kind' "$LOGS/$N.pipe" || fail "the JSON or the table missing from the pipe"
end

begin "lights: --json /dev/stdout with stdout appended to log.txt"
printf 'earlier log line\n' >log.txt
snap; run ok "\$L lights sky:16x8 --method median-cut -k 2 --json /dev/stdout >> log.txt"
grep -q 'earlier log line' log.txt || fail "log.txt's earlier contents lost (the file was replaced, not appended to)"
grep -q 'light kind' log.txt || fail "the printed light table lost"
end log.txt

begin "lights: --gltf so.gltf a symlink to /dev/stdout, stdout to out.txt"
ln -s /dev/stdout so.gltf
snap; run ok "\$L lights sky:16x8 --method median-cut -k 2 --gltf so.gltf > out.txt"
grep -q 'light kind' out.txt || fail "the printed light table lost (out.txt holds only the glTF)"
end out.txt so.gltf

begin "lights: --gltf /dev/stdout (no extension)"
snap; run any "\$L lights sky:16x8 --method median-cut -k 2 --gltf /dev/stdout > out.txt"
[ "$RC" = 2 ] || fail "exit $RC: a --gltf name that is neither .gltf nor .glb must be refused (usage)"
end out.txt

begin "render: -o so.exr a symlink to /dev/stdout, stdout appended to keep.log"
printf 'keep me\n' >keep.log; ln -s /dev/stdout so.exr
snap; run ok "\$L render --scene spheres $R -o so.exr --no-sidecar >> keep.log"
grep -q 'keep me' keep.log || fail "keep.log's earlier contents lost (replaced by the EXR)"
end keep.log so.exr

begin "convert: OUT a symlink to /dev/stdout, piped: the same bytes as a file"
"$L" convert sky:8x4 "$LOGS/$N.ref.pfm" >/dev/null 2>&1; ln -s /dev/stdout so.pfm
snap; run ok "\$L convert sky:8x4 so.pfm | cat > \$T/logs/$N.pipe"
cmp -s "$LOGS/$N.pipe" "$LOGS/$N.ref.pfm" || fail "the piped PFM differs from the file"
end so.pfm

# ==== 3. folders and devices =============================================================

for c in "convert sky:8x4 nodir/x.pfm" "lights sky:16x8 --method median-cut -k 2 --json nodir/a.json" \
    "lights sky:16x8 --method median-cut -k 2 --gltf nodir/a.gltf" "lights sky:16x8 --method median-cut -k 2 --png nodir/a.png" \
    "render --scene spheres $R -o nodir/a.exr" "render --scene spheres $R -o a.exr --png nodir/a.png" \
    "render --scene spheres $R -o a.exr --sidecar nodir/a.json" "compare m.pfm m.pfm --diff nodir/d.pfm" \
    "compare m.pfm m.pfm --map nodir/d.png" "luminaire create nodir/l.json --preset small" \
    "sky --size 8x4 -o nodir/s.exr" "studio --size 8x4 -o nodir/s.exr"; do
    begin "${c%% *}: an output in a missing folder (${c##* })"
    cp "$FIX/map.pfm" m.pfm
    snap; run fail "\$L $c"; end
done

for c in "convert sky:8x4 f.pfm/x.pfm" "lights sky:16x8 --method median-cut -k 2 --json f.pfm/a.json" \
    "render --scene spheres $R -o f.pfm/a.exr" "render --scene spheres $R -o a.exr --sidecar f.pfm/s.json" \
    "compare f.pfm f.pfm --diff f.pfm/d.pfm" "luminaire create f.pfm/l.json --preset small" \
    "bench s.json --out f.pfm/o" "demo --out f.pfm/o --time 0.01" "demo --out f.pfm --time 0.01"; do
    begin "${c%% *}: an output under a regular file (${c##* })"
    cp "$FIX/map.pfm" f.pfm; cp "$FIX/suite.json" s.json
    snap; run fail "\$L $c"; end
done

for c in "convert sky:8x4 /proc/x.pfm" "convert sky:8x4 /sys/x.pfm" "lights sky:16x8 --method median-cut -k 2 --json /proc/self/a.json" \
    "render --scene spheres $R -o /sys/a.exr" "luminaire create /sys/l.json --preset small" "bench s.json --out /proc/sweep-out" \
    "demo --out /sys/sweep-demo --time 0.01"; do
    begin "${c%% *}: an output where nothing can be made (${c##* })"
    cp "$FIX/suite.json" s.json
    snap; run fail "\$L $c"; end
done

# /dev/full: every write must fail with an error (exit non-zero) and leave /dev/full a device
for c in "convert sky:8x4 full.pfm" "convert sky:64x32 full.exr" "convert sky:8x4 full.exr" "studio --size 8x4 -o full.exr" \
    "compare m.pfm m.pfm --diff full.exr" "convert sky:8x4 full.png" "convert sky:8x4 full.hdr" \
    "lights sky:16x8 --method median-cut -k 2 --json /dev/full" "lights sky:16x8 --method median-cut -k 2 --gltf full.gltf" "lights sky:16x8 --method median-cut -k 2 --gltf full.glb" \
    "lights sky:16x8 --method median-cut -k 2 --png full.png" "render --scene spheres $R -o full.exr" \
    "render --scene spheres $R -o a.exr --sidecar /dev/full" "render --scene spheres $R -o a.exr --png full.png" \
    "compare m.pfm m.pfm --diff full.pfm" "compare m.pfm m.pfm --map full.png" "sky --size 8x4 -o full.exr" \
    "luminaire create full.json --preset small" "luminaire render lum.json $R -o full.exr" \
    "sample sky:16x8 --method inversion -n 100 > /dev/full" "pdf sky:16x8 --method inversion < dirs.txt > /dev/full" \
    "info sky:16x8 > /dev/full" "info sky:16x8 --json > /dev/full" "compare m.pfm m.pfm --json > /dev/full" \
    "luminaire info lum.json > /dev/full" "bench-samplers sky:16x8 --runs 1 --samples 1000 --methods inversion > /dev/full" \
    "lights sky:16x8 --method median-cut -k 2 > /dev/full" "--help > /dev/full" "convert --help > /dev/full"; do
    begin "/dev/full: ${c}"
    for f in full.pfm full.exr full.png full.hdr full.json full.gltf full.glb; do ln -s /dev/full $f; done
    cp "$FIX/map.pfm" m.pfm; lum; printf '0 1 0\n1 0 0\n' >dirs.txt
    snap; run fail "\$L $c"
    stderr_says 'space|write' || note "no write error named on stderr"
    end a.exr a.json
done

begin "sample: stdout closed (>&-)"
snap; run fail "\$L sample sky:16x8 --method inversion -n 10 >&-"; end

# an existing output that is a folder, a link to one, a dangling link, a FIFO, /dev/null
for c in "convert sky:8x4 X.pfm" "lights sky:16x8 --method median-cut -k 2 --json X.pfm" \
    "render --scene spheres $R -o X.exr" "render --scene spheres $R -o a.exr --sidecar X.pfm" \
    "compare m.pfm m.pfm --diff X.pfm" "luminaire create X.json --preset small"; do
    begin "${c%% *}: the output is an existing folder (${c##* })"
    cp "$FIX/map.pfm" m.pfm; mkdir X.pfm X.exr X.json; echo keep >X.pfm/f; echo keep >X.exr/f; echo keep >X.json/f
    snap; run fail "\$L $c"; end
    begin "${c%% *}: the output is a symlink to a folder (${c##* })"
    cp "$FIX/map.pfm" m.pfm; mkdir D; echo keep >D/f; ln -s D X.pfm; ln -s D X.exr; ln -s D X.json
    snap; run fail "\$L $c"; end
done

for c in "convert sky:8x4 X.pfm" "lights sky:16x8 --method median-cut -k 2 --json X.pfm" \
    "render --scene spheres $R -o X.exr --no-sidecar" "compare m.pfm t.pfm --diff X.pfm"; do
    begin "${c%% *}: the output is a dangling symlink (${c##* })"
    cp "$FIX/map.pfm" m.pfm; cp "$FIX/test.pfm" t.pfm; mkdir tgt; ln -s tgt/new.pfm X.pfm; ln -s tgt/new.exr X.exr
    snap; run ok "\$L $c"
    [ -n "$(ls tgt)" ] || note "nothing written where the link points"
    end X.pfm X.exr 'tgt/*'
done

begin "convert: the output is a symlink to a file in another folder"
mkdir far; cp "$FIX/map.pfm" far/old.pfm; ln -s far/old.pfm X.pfm
snap; run ok "\$L convert studio:8x4 X.pfm"
[ -L X.pfm ] || fail "the link X.pfm was replaced"
end far/old.pfm

for c in "convert sky:8x4 F.pfm" "lights sky:16x8 --method median-cut -k 2 --json F.pfm"; do
    begin "${c%% *}: the output is a FIFO with no reader (${c##* })"
    mkfifo F.pfm
    snap; CMD="\$L $c"; echo "$CMD" >"$LOGS/$N.cmd"
    timeout 10 bash -c "$CMD" >"$LOGS/$N.out" 2>"$LOGS/$N.err"; RC=$?
    [ "$RC" = 124 ] && warn "blocks opening the FIFO until a reader comes (killed after 10 s; no error, no data lost)"
    [ -p F.pfm ] || fail "the FIFO was replaced"
    end
done

begin "convert: the output is a FIFO with a reader (the bytes of a file)"
mkfifo F.pfm; "$L" convert sky:8x4 "$LOGS/$N.ref.pfm" >/dev/null 2>&1
snap; (timeout 15 cat F.pfm >"$LOGS/$N.got" &)
run ok "\$L convert sky:8x4 F.pfm"; sleep 0.2
cmp -s "$LOGS/$N.got" "$LOGS/$N.ref.pfm" || fail "the reader got other bytes"
[ -p F.pfm ] || fail "the FIFO was replaced"
end

begin "render: --png and --sidecar to FIFOs with readers"
mkfifo F.png F.json
snap; for f in F.png F.json; do (timeout 15 cat $f >"$LOGS/$N.$f" &); done
run ok "\$L render --scene spheres $R -o r.exr --png F.png --sidecar F.json"; sleep 0.2
head -c 4 "$LOGS/$N.F.png" | od -An -c | grep -q 'P   N   G' || fail "the PNG reader got no PNG"
grep -q '"spp"' "$LOGS/$N.F.json" || fail "the sidecar reader got no sidecar"
end

begin "render: -o a FIFO with a reader (EXR)"
mkfifo F.exr
snap; (timeout 15 cat F.exr >"$LOGS/$N.F.exr" &)
run any "\$L render --scene spheres $R -o F.exr --no-sidecar"; sleep 0.2
if [ "$RC" != 0 ]; then
    warn "EXR cannot be written to a FIFO (exit $RC: $(head -c 90 "$LOGS/$N.err")); the reader got $(stat -c %s "$LOGS/$N.F.exr") bytes of a partial file"
else
    "$L" info "$LOGS/$N.F.exr" >/dev/null 2>&1 || fail "exit 0 but the reader got no valid EXR"
fi
[ -p F.exr ] || fail "the FIFO was replaced"
end

for c in "convert sky:8x4 n.pfm" "lights sky:16x8 --method median-cut -k 2 --json /dev/null" \
    "lights sky:16x8 --method median-cut -k 2 --gltf n.glb --png n.png" "render --scene spheres $R -o n.exr --png n.png --sidecar /dev/null" \
    "compare m.pfm t.pfm --diff n.pfm --map n.png" "sky --size 8x4 -o n.exr"; do
    begin "/dev/null as output: $c"
    for f in n.pfm n.exr n.png n.glb; do ln -s /dev/null $f; done; cp "$FIX/map.pfm" m.pfm; cp "$FIX/test.pfm" t.pfm
    snap; run ok "\$L $c"; end
done

begin "lights: --json /dev/null --gltf n.gltf -> /dev/null (two outputs to /dev/null)"
ln -s /dev/null n.gltf
snap; run any "\$L lights sky:16x8 --method median-cut -k 2 --json /dev/null --gltf n.gltf"
[ "$RC" = 2 ] && warn "refused: --json and --gltf 'the same file' although both are /dev/null"
end

begin "convert: OUT /dev/null (no extension)"
snap; run any "\$L convert sky:8x4 /dev/null"
[ "$RC" = 0 ] || note "refused for its extension (a symlink n.pfm -> /dev/null works)"
end

begin "convert: a 255-byte output name (its temporary name would be 263)"
name=$(printf 'a%.0s' $(seq 1 251)).pfm
snap; run ok "\$L convert sky:8x4 $name"
[ "$RC" != 0 ] && stderr_says 'too long' && WARNS=("a valid 255-byte name refused after the work: the hidden temporary .NAME.XXXXXX is longer than NAME_MAX")
end "$name"

begin "render: a 255-byte -o name after the render (default sidecar)"
name=$(printf 'b%.0s' $(seq 1 251)).exr
snap; run ok "\$L render --scene spheres $R -o $name --no-sidecar"
[ "$RC" != 0 ] && stderr_says 'too long' && WARNS=("the render is done, then its 255-byte output name is refused (temporary name too long); the work is lost")
end "$name"

begin "convert: an existing output with mode 600 is replaced"
"$L" convert sky:8x4 o.pfm >/dev/null 2>&1; chmod 600 o.pfm
snap; run ok "\$L convert studio:8x4 o.pfm"; end o.pfm

begin "convert: an existing output with a second hard link (the link keeps the old bytes)"
"$L" convert sky:8x4 o.pfm >/dev/null 2>&1; ln o.pfm backup.pfm
snap; run ok "\$L convert studio:8x4 o.pfm"
[ "$(stat -c %h o.pfm)" = 1 ] && note "o.pfm is a new inode: the hard link backup.pfm keeps the old map"
end o.pfm

begin "luminaire create: the manifest a symlink to /dev/null"
ln -s /dev/null n.json
snap; run any "\$L luminaire create n.json --preset small"
note "exit $RC; n.images: $(ls n.images 2>/dev/null | wc -l) images"
end 'n.images/*' n.images

# ==== 3b. a full file system (an 8 MiB tmpfs, when this user may mount one) ==============
# The outputs are written to a temporary beside them and renamed: on a full file system
# every write must fail (exit non-zero) and leave the earlier output as it was.

FULLFS=$T/fullfs
mkdir -p "$FULLFS"
if mount -t tmpfs -o size=8m sweep-full "$FULLFS" 2>/dev/null; then MOUNTED=1; fi

full_case() { # full_case NAME 'setup' 'command' OUTPUT...: the command on a full file system
    local name=$1 setup=$2 cmd=$3
    shift 3
    begin "full file system: $name"
    rm -rf "${FULLFS:?}"/*
    mkdir "$FULLFS/c"; cd "$FULLFS/c" || exit 2
    CDIR=$FULLFS/c
    cp "$FIX/map.pfm" m.pfm; cp "$FIX/test.pfm" t.pfm
    bash -c "$setup" >/dev/null 2>&1
    dd if=/dev/zero of=fill bs=4k 2>/dev/null
    dd if=/dev/zero of=fill2 bs=512 2>/dev/null
    snap; run any "$cmd"
    local o
    if [ "$RC" = 0 ]; then
        for o in "$@"; do
            case $o in
            *.json | *.gltf) python3 -c "import json,sys; json.load(open(sys.argv[1]))" "$o" 2>/dev/null ||
                fail "exit 0, but $o is $(stat -c %s "$o" 2>/dev/null || echo no) bytes and not JSON (the earlier file lost)" ;;
            *) "$L" info "$o" >/dev/null 2>&1 ||
                fail "exit 0, but $o is $(stat -c %s "$o" 2>/dev/null || echo no) bytes and unreadable (the earlier file lost)" ;;
            esac
        done
        end "$@"
    else
        end # an error: nothing may have changed
    fi
    rm -rf "${FULLFS:?}"/*
}

if [ "${MOUNTED:-0}" = 1 ]; then
    full_case "convert sky:8x4 o.exr (small EXR) over o.exr" '$L convert studio:8x4 o.exr' '$L convert sky:8x4 o.exr' o.exr
    full_case "convert sky:64x32 o.exr over o.exr" '$L convert studio:64x32 o.exr' '$L convert sky:64x32 o.exr' o.exr
    full_case "convert --half sky:8x4 o.exr" '$L convert studio:8x4 o.exr' '$L convert sky:8x4 o.exr --half --compression none' o.exr
    full_case "convert sky:8x4 o.pfm over o.pfm" '$L convert studio:8x4 o.pfm' '$L convert sky:8x4 o.pfm' o.pfm
    full_case "convert sky:8x4 o.hdr over o.hdr" '$L convert studio:8x4 o.hdr' '$L convert sky:8x4 o.hdr' o.hdr
    full_case "convert sky:8x4 o.png over o.png" '$L convert studio:8x4 o.png' '$L convert sky:8x4 o.png' o.png
    full_case "sky --size 8x4 -o o.exr" '$L convert studio:8x4 o.exr' '$L sky --size 8x4 -o o.exr' o.exr
    full_case "studio --size 8x4 -o o.exr" '$L convert sky:8x4 o.exr' '$L studio --size 8x4 -o o.exr' o.exr
    full_case "compare --diff d.exr (small EXR)" '$L compare m.pfm m.pfm --diff d.exr' '$L compare m.pfm t.pfm --diff d.exr' d.exr
    full_case "compare --map f.png" '$L compare m.pfm m.pfm --map f.png' '$L compare m.pfm t.pfm --map f.png' f.png
    full_case "render 8x6 -o r.exr with its sidecar" '$L render --scene spheres --size 8x6 --spp 1 --quiet -o r.exr' \
        '$L render --scene spheres --size 8x6 --spp 1 --quiet --seed 4 -o r.exr' r.exr r.json
    full_case "render 16x12 -o r.exr --png r.png" '$L render --scene spheres $R -o r.exr --png r.png' \
        '$L render --scene spheres $R --seed 4 -o r.exr --png r.png' r.exr r.json r.png
    full_case "lights --json --gltf --png" '$L lights m.pfm --method median-cut -k 2 --json j.json --gltf g.gltf --png p.png' \
        '$L lights t.pfm --method median-cut -k 2 --json j.json --gltf g.gltf --png p.png' j.json g.gltf p.png
    full_case "luminaire create over a luminaire (EXR images)" '$L luminaire create lum.json --preset small' \
        '$L luminaire create lum.json --preset small --basis bspline' lum.json
    full_case "demo --out d over an earlier demo" '$L demo --out d --time 0.01' '$L demo --out d --time 0.01' \
        d/sky.exr d/spheres-inversion.exr d/spheres-kdtree.exr d/spheres-reference.exr d/spheres-inversion.json
else
    skip "full file system" "cannot mount a tmpfs here (not root, or no permission)"
fi

# ==== 4. interrupts =======================================================================

# timed: poll until the temporary file appears, then signal; the earlier output must be
# whole (the old bytes, or the complete new ones) and nothing hidden left
"$L" render --scene spheres --size 320x240 --spp 1 --quiet --seed 2 -o "$FIX/r-new.exr" --no-sidecar >/dev/null 2>&1
for sig in INT TERM INT TERM; do
    begin "render: SIG$sig while the 320x240 EXR is written (timed)"
    "$L" render --scene spheres --size 320x240 --spp 1 --quiet -o r.exr --no-sidecar >/dev/null 2>&1
    old=$(sha256sum <r.exr); new=$(sha256sum <"$FIX/r-new.exr")
    snap; CMD="\$L render --scene spheres --size 320x240 --spp 1 --quiet --seed 2 -o r.exr --no-sidecar & poll .r.exr.*; kill -$sig"
    "$L" render --scene spheres --size 320x240 --spp 1 --quiet --seed 2 -o r.exr --no-sidecar >/dev/null 2>&1 &
    p=$!; until compgen -G ".r.exr.*" >/dev/null || ! kill -0 $p 2>/dev/null; do :; done
    kill -$sig $p 2>/dev/null; { wait $p; } 2>/dev/null; RC=$?
    now=$(sha256sum <r.exr)
    [ "$now" = "$old" ] || [ "$now" = "$new" ] || fail "r.exr is neither the old render nor the new one"
    end r.exr
done

begin "convert: SIGTERM as the 1024x512 PFM temporary appears, 30 times (timed)"
"$L" convert sky:8x4 o.pfm >/dev/null 2>&1
snap; CMD="\$L convert sky:1024x512 o.pfm & poll .o.pfm.*; kill -TERM  (x30)"
leaks=0
for i in $(seq 1 30); do
    "$L" convert sky:1024x512 o.pfm >/dev/null 2>&1 &
    p=$!; until compgen -G ".o.pfm.*" >/dev/null || ! kill -0 $p 2>/dev/null; do :; done
    kill -TERM $p 2>/dev/null; { wait $p; } 2>/dev/null
    if compgen -G ".o.pfm.*" >/dev/null; then leaks=$((leaks + 1)); rm -f .o.pfm.*; fi
done
[ $leaks -gt 0 ] && fail "$leaks of 30 runs left a hidden .o.pfm.XXXXXX (0 bytes, mode 600)"
end o.pfm

begin "luminaire create: SIGINT as the staging folder appears (timed)"
lum
snap; CMD="\$L luminaire create lum.json --preset small & poll lum.images.new-*; kill -INT"
"$L" luminaire create lum.json --preset small >/dev/null 2>&1 &
p=$!; until compgen -G "lum.images.new-*" >/dev/null || ! kill -0 $p 2>/dev/null; do :; done
kill -INT $p 2>/dev/null; { wait $p; } 2>/dev/null; RC=$?
"$L" luminaire info lum.json >/dev/null 2>&1 || fail "lum.json no longer loads"
end lum.json 'lum.images/*'

begin "bench: SIGINT to the process group after the first results (timed)"
cp "$FIX/suite.json" s.json
"$L" bench s.json --out o --threads 1 >/dev/null 2>&1
rm -f o/results/*studio*
snap; CMD="setsid \$L bench s.json --out o --threads 1 & poll o/results; kill -INT -PGID"
setsid "$L" bench s.json --out o --threads 1 >/dev/null 2>&1 &
p=$!; until [ "$(ls o/results 2>/dev/null | wc -l)" -ge 5 ] || ! kill -0 $p 2>/dev/null; do :; done
kill -INT -- -$p 2>/dev/null; { wait $p; } 2>/dev/null; RC=$?; sleep 0.3
"$L" bench s.json --out o --threads 1 >"$LOGS/$N.resume" 2>&1 || fail "the resumed run failed"
[ "$(ls o/results | wc -l)" = 8 ] || fail "the resumed run has $(ls o/results | wc -l) of 8 results"
end 'o/*'

begin "demo: SIGTERM as sky.exr is written (timed)"
snap; CMD="\$L demo --out d --time 0.02 & poll d/.sky.exr.*; kill -TERM"
"$L" demo --out d --time 0.02 >/dev/null 2>&1 &
p=$!; until compgen -G "d/.sky.exr.*" >/dev/null || ! kill -0 $p 2>/dev/null; do :; done
kill -TERM $p 2>/dev/null; { wait $p; } 2>/dev/null; RC=$?
end 'd/*' d

# injected: the signal raised in the process right after the call returns
inject() { # inject NAME HOOK MATCH SIG NTH 'command' ALLOWED...: the command under the shim
    local name=$1 hook=$2 match=$3 sig=$4 nth=$5 cmd=$6
    shift 6
    CMD="SWEEP_HOOK=$hook SWEEP_MATCH='$match' SWEEP_NTH=$nth SWEEP_SIG=$sig LD_PRELOAD=hook.so $cmd"
    echo "$CMD" >"$LOGS/$N.cmd"
    (SWEEP_HOOK=$hook SWEEP_MATCH=$match SWEEP_NTH=$nth SWEEP_SIG=$sig LD_PRELOAD=$HOOK \
        timeout 20 bash -c "$cmd" >"$LOGS/$N.out" 2>"$LOGS/$N.err"; exit $?) 2>/dev/null
    RC=$?
    case $RC in 130 | 143) ;; *) note "exit $RC: the signal did not fire (hook $hook $match)" ;; esac
}

if [ -n "$HOOK" ]; then
    for sig in TERM INT; do
        begin "convert: SIG$sig right after mkstemp made the temporary (injected)"
        "$L" convert sky:8x4 o.pfm >/dev/null 2>&1
        snap; inject x mkstemp .o.pfm. $sig 1 "\$L convert studio:8x4 o.pfm"; end o.pfm

        begin "render: SIG$sig right after the EXR's rename, before the sidecar (injected)"
        "$L" render --scene spheres $R -o r.exr >/dev/null 2>&1
        snap; inject x rename r.exr $sig 1 "\$L render --scene spheres $R --seed 3 -o r.exr"
        end r.exr r.json
    done

    begin "lights: SIGTERM right after --json's temporary is made (injected)"
    echo '{"old": 1}' >j.json
    snap; inject x mkstemp .j.json. TERM 1 "\$L lights sky:16x8 --method median-cut -k 2 --json j.json --gltf g.gltf"; end

    begin "luminaire create: SIGTERM right after the staging folder is made (injected)"
    lum; snap; inject x mkdtemp .images.new- TERM 1 "\$L luminaire create lum.json --preset small --basis bspline"
    "$L" luminaire info lum.json >/dev/null 2>&1 || fail "lum.json no longer loads"
    end

    begin "luminaire create: SIGINT right after the 3rd image's temporary is made (injected)"
    lum; snap; inject x mkstemp .a00 INT 3 "\$L luminaire create lum.json --preset small --basis bspline"
    "$L" luminaire info lum.json >/dev/null 2>&1 || fail "lum.json no longer loads"
    end

    begin "luminaire create: SIGINT right after the old images folder stepped aside (injected)"
    lum; snap; inject x rename .images.old- INT 1 "\$L luminaire create lum.json --preset small --basis bspline"
    "$L" luminaire info lum.json >/dev/null 2>"$LOGS/$N.info" || fail "lum.json no longer loads: $(head -1 "$LOGS/$N.info")"
    # the swap holds the signal back until the manifest and its images are a pair again:
    # the old luminaire or the new one, whole (it loads, checked by its digest)
    end lum.json 'lum.images/*'

    begin "luminaire create: SIGTERM right after the new images took the folder's name (injected)"
    lum; snap; inject x rename =lum.images TERM 1 "\$L luminaire create lum.json --preset small --basis bspline"
    "$L" luminaire info lum.json >/dev/null 2>"$LOGS/$N.info" || fail "lum.json no longer loads: $(head -1 "$LOGS/$N.info")"
    end lum.json 'lum.images/*'

    begin "luminaire create: SIGTERM right after the manifest's temporary is made (injected)"
    lum; snap; inject x mkstemp .lum.json. TERM 1 "\$L luminaire create lum.json --preset small --basis bspline"
    "$L" luminaire info lum.json >/dev/null 2>"$LOGS/$N.info" || fail "lum.json no longer loads: $(head -1 "$LOGS/$N.info")"
    end lum.json 'lum.images/*'

    begin "bench: SIGTERM right after the report's results.csv (injected)"
    cp "$FIX/suite.json" s.json; "$L" bench s.json --out o --threads 1 >/dev/null 2>&1
    snap; inject x rename results.csv TERM 1 "\$L bench s.json --out o --threads 1"; end o/results.csv

    begin "demo: SIGINT right after DIR/sky.exr (injected)"
    snap; inject x rename d/sky.exr INT 1 "\$L demo --out d --time 0.02"; end 'd/*' d
else
    skip "injected interrupts" "no C compiler for the LD_PRELOAD shim"
fi

# ==== 5. inputs ignored or replaced ======================================================

twice() { # twice NAME 'command with an option given twice' [files that show which won]
    begin "option twice: $1"
    cp "$FIX/map.pfm" m.pfm; cp "$FIX/test.pfm" t.pfm
    snap; run any "\$L $2"
    if [ "$RC" = 0 ]; then
        if stderr_says 'twice|more than once|again|overrid|ignor'; then note "said on stderr"
        else warn "accepted; the last one wins without a word${3:+ ($3)}"; fi
    fi
    end
}
twice "render -o a.exr -o b.exr" "render --scene spheres $R -o a.exr -o b.exr" "a.exr never written"
twice "render --png a.png --png b.png" "render --scene spheres $R -o r.exr --png a.png --png b.png"
twice "render --env sky:32x16 --env studio:32x16" "render --scene spheres $R --env sky:32x16 --env studio:32x16 -o r.exr"
twice "render --spp 1 --spp 2" "render --scene spheres --size 16x12 --quiet --spp 1 --spp 2 -o r.exr"
twice "convert --tonemap aces --tonemap clamp" "convert m.pfm o.png --tonemap aces --tonemap clamp"
twice "sky -o a.exr -o b.exr" "sky --size 8x4 -o a.exr -o b.exr" "a.exr never written"
twice "lights --json a.json --json b.json" "lights m.pfm --method median-cut -k 2 --json a.json --json b.json" "a.json never written"
twice "lights --method median-cut --method fhis" "lights m.pfm --method median-cut --method fhis -k 2"
twice "lights -k 2 -k 3" "lights m.pfm --method median-cut -k 2 -k 3"
twice "sample --seed 1 --seed 2" "sample m.pfm --method inversion -n 2 --seed 1 --seed 2"
twice "compare --diff a.pfm --diff b.pfm" "compare m.pfm t.pfm --diff a.pfm --diff b.pfm" "a.pfm never written"
twice "luminaire create --preset small --preset bike" "luminaire create l.json --preset bike --preset small"
twice "bench --out a --out b" "bench $FIX/suite.json --out a --out b --threads 1" "nothing in a"
twice "demo --out a --out b" "demo --out a --out b --time 0.01" "nothing in a"

for c in "convert sky:8x4 o.pfm --frobnicate" "sky --frobnicate -o o.exr" "studio --frobnicate -o o.exr" \
    "render --scene spheres $R -o o.exr --frobnicate" "lights sky:16x8 --method median-cut --frobnicate" \
    "luminaire create l.json --frobnicate" "luminaire render preset:small $R -o o.exr --frobnicate" \
    "compare m.pfm m.pfm --frobnicate" "bench s.json --frobnicate" "demo --frobnicate" \
    "sample sky:16x8 --method inversion -n 1 --frobnicate" "pdf sky:16x8 --method inversion --frobnicate" \
    "info sky:16x8 --frobnicate" "bench-samplers sky:16x8 --frobnicate" "luminaire info preset:small --frobnicate" \
    "convert sky:8x4 o.pfm extra.pfm" "render --scene spheres $R -o o.exr extra.json"; do
    begin "unknown argument: $c"
    cp "$FIX/map.pfm" m.pfm; cp "$FIX/suite.json" s.json
    snap; run usage "\$L $c"; end
done

begin "lights: --json with no value swallows --masks"
snap; run any "\$L lights sky:16x8 --method median-cut -k 2 --json --masks"
[ -e ./--masks ] && warn "wrote a file named '--masks' and no masks (the option taken as --json's path)"
end ./--masks --masks

begin "render: --sidecar with no value swallows --quiet"
snap; run any "\$L render --scene spheres --size 16x12 --spp 1 -o o.exr --sidecar --quiet"
[ -e ./--quiet ] && warn "wrote the sidecar to a file named '--quiet' and was not quiet"
end o.exr --quiet

for fmt in pfm hdr exr png; do
    begin "info: a $fmt map with trailing garbage"
    cp "$FIX/map.$fmt" g.$fmt; printf 'TRAILING GARBAGE\n' >>g.$fmt
    snap; run any "\$L info g.$fmt"
    if [ "$RC" = 0 ]; then
        if [ $fmt = pfm ]; then grep -q "ignored" "$LOGS/$N.err" ||
            fail "read as a 16x8 map without a word: the bytes after the pixels are ignored"
        else warn "accepted without a word (bytes after the image ignored)"; fi
    fi
    end
done

begin "convert: a PFM whose data holds more rows than its header says (16x8 header, 16x9 data)"
python3 - <<'EOF'
import struct
w, h = 16, 9
open('g.pfm', 'wb').write(b'PF\n16 8\n-1.0\n' + struct.pack('<%df' % (w * h * 3), *[float(i % 7) for i in range(w * h * 3)]))
EOF
snap; run any "\$L convert g.pfm o.exr"
[ "$RC" = 0 ] && ! grep -q "ignored" "$LOGS/$N.err" &&
    fail "converted as 16x8 without a word; the 9th row of data dropped"
end o.exr

begin "exr: R,G,B plus a diffuse.R/G/B layer: the base layer is read"
mkexr x.exr 4 2 R=1 G=2 B=3 diffuse.R=100 diffuse.G=200 diffuse.B=300
snap; run ok "\$L convert x.exr o.pfm"
[ "$RC" = 0 ] && { pfm_is o.pfm 1 2 3 || fail "o.pfm is not the base layer (1, 2, 3)"; }
stderr_says 'layer|ignor' || note "the other layer is ignored without a word"
end o.pfm

begin "exr: only a diffuse.R/G/B layer (no base R,G,B)"
mkexr x.exr 4 2 diffuse.R=100 diffuse.G=200 diffuse.B=300
snap; run fail "\$L convert x.exr o.pfm"; end

begin "exr: R,G,B,A with A = 0: RGB read, alpha not multiplied in"
mkexr x.exr 4 2 R=1 G=2 B=3 A=0
snap; run ok "\$L convert x.exr o.pfm"
[ "$RC" = 0 ] && { pfm_is o.pfm 1 2 3 || fail "o.pfm is not (1, 2, 3)"; }
end o.pfm

begin "exr: Y only (grey)"
mkexr x.exr 4 2 Y=5
snap; run ok "\$L convert x.exr o.pfm"
[ "$RC" = 0 ] && { pfm_is o.pfm 5 5 5 || fail "o.pfm is not (5, 5, 5)"; }
end o.pfm

begin "exr: R, G and Y (no B): are R and G dropped for Y?"
mkexr x.exr 4 2 R=1 G=2 Y=7
snap; run any "\$L convert x.exr o.pfm"
[ "$RC" = 0 ] && pfm_is o.pfm 7 7 7 && warn "read as grey Y = 7; the R and G channels ignored without a word"
end o.pfm

begin "exr: R, G, B, Y: RGB wins over Y"
mkexr x.exr 4 2 R=1 G=2 B=3 Y=9
snap; run ok "\$L convert x.exr o.pfm"
[ "$RC" = 0 ] && { pfm_is o.pfm 1 2 3 || fail "o.pfm is not (1, 2, 3)"; }
end o.pfm

for s in 1x1 2x1 1x2; do
    begin "map $s: info, sample, pdf, convert --resize, render --env"
    snap; run ok "\$L info sky:$s && \$L sample sky:$s --method inversion -n 4 && echo '0 1 0' | \$L pdf sky:$s --method inversion && \$L convert sky:64x32 r.pfm --resize $s && \$L render --scene spheres $R --env sky:$s -o r.exr"
    if [ "$RC" = 0 ]; then
        grep -v 'replaced' "$LOGS/$N.out" | grep -qiE '(^|[ ,:])[-+]?(nan|inf)([ ,]|$)' && fail "a NaN or Inf printed"
        p0=$("$L" info sky:64x32 --json | python3 -c 'import json,sys; print(json.load(sys.stdin)["power"])')
        p1=$("$L" info r.pfm --json | python3 -c 'import json,sys; print(json.load(sys.stdin)["power"])')
        python3 -c "import sys; a,b=$p0,$p1; sys.exit(0 if abs(a-b) <= 1e-3*abs(a) else 1)" ||
            fail "--resize $s changed the power: $p0 -> $p1"
    fi
    end r.pfm r.exr r.json
done

begin "lights: -k 64 on a 1x1 map"
snap; run fail "\$L lights sky:1x1 --method median-cut -k 64 --json l.json --gltf l.gltf"; end

begin "lights: -k 0"
snap; run usage "\$L lights sky:16x8 --method median-cut -k 0 --json l.json --gltf l.gltf"; end

for m in median-cut fhis wu; do
    begin "lights: a black map by $m: JSON and glTF valid, K lights of power 0"
    python3 -c "
import struct
open('black.pfm','wb').write(b'PF\n4 2\n-1.0\n' + struct.pack('<24f', *[0.0]*24))"
    snap; run ok "\$L lights black.pfm --method $m -k 2 --json l.json --gltf l.gltf --png l.png"
    if [ "$RC" = 0 ]; then
        python3 - <<'EOF' || fail "l.json or l.gltf invalid"
import json, sys
j = json.load(open('l.json')); g = json.load(open('l.gltf'))
lights = g['extensions']['KHR_lights_punctual']['lights']
assert len(lights) >= 1, 'KHR_lights_punctual needs at least one light'
assert all(n['extensions']['KHR_lights_punctual']['light'] < len(lights) for n in g['nodes'])
assert len(j['lights']) == len(lights)
EOF
    fi
    end l.json l.gltf l.png
done

begin "a file named 'sky' in the working folder"
cp "$FIX/test.pfm" sky
snap; run ok "\$L info sky"
grep -q 'file.*sky' "$LOGS/$N.out" && grep -q 'procedural\|1024 x 512' "$LOGS/$N.out" &&
    warn "'sky' names the procedural map; the file ./sky is ignored without a word (./sky reads it)"
end

begin "pdf: a malformed stdin line"
snap; run fail "printf '0 1 0\nabc\n0 0 1\n' | \$L pdf sky:16x8 --method inversion"
[ "$(wc -l <"$LOGS/$N.out")" -gt 1 ] && fail "lines after the malformed one printed"
end

begin "pdf: a zero direction"
snap; run any "printf '0 0 0\n' | \$L pdf sky:16x8 --method inversion"
[ "$RC" = 0 ] && grep -qiE '(^|[ ,:])[-+]?(nan|inf)([ ,]|$)' "$LOGS/$N.out" && fail "a NaN printed for the zero direction"
end

begin "info: a FIFO as input"
cp "$FIX/map.pfm" m.pfm; mkfifo F.pfm
snap; (timeout 10 cat m.pfm >F.pfm 2>/dev/null &)
run any "\$L info F.pfm"
[ "$RC" = 0 ] || note "refused: $(head -c 80 "$LOGS/$N.err")"
timeout 1 cat F.pfm >/dev/null 2>&1 # release the writer
end

# ==== summary =============================================================================
echo "# $N cases: $NPASS PASS, $NFAIL FAIL, $NWARN WARN, $NSKIP SKIP in $(($(date +%s) - START)) s"
if [ $NFAIL -gt 0 ]; then
    echo "# FAILs:"
    printf '%s\n' "${FAIL_LINES[@]}"
    exit 1
fi
exit 0
