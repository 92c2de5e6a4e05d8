#!/usr/bin/env bash
# make mutate: applies each mutant of tests/mutants/*.txt in turn (tests/mutants/README.md),
# rebuilds the test program it names in build-mutate/, runs it, restores the file, and
# prints whether the module's own tests caught it, then the score per module.  Exit 1 if
# any non-equivalent mutant survives.
#
# Mutants are applied to a copy of the sources ($MUTATE_DIR/tree, refreshed file by file
# at each start), never to the working tree: an editor, a build or a second mutate run
# beside it never sees a mutated file.
#
#   scripts/mutate.sh [MODULE...]        (default: every file in tests/mutants)
#   MUTATE_DIR=build-mutate-2 scripts/mutate.sh lights     (a second run beside the first)
#   MUTATE_ONLY=ID scripts/mutate.sh MODULE                (one mutant of a module)
#   scripts/mutate.sh --check                              (no build: every "from" occurs
#                                                           exactly once in its file; a test)
set -uo pipefail
cd "$(dirname "$0")/.."
root=$PWD
if [ "${1:-}" = --check ]; then
    # the list stays applicable as code moves: a stale mutant is an error, not a skip
    perl -00 -e '
        my $bad = 0; my $n = 0;
        for my $f (glob "tests/mutants/*.txt") {
            open my $h, "<", $f or die; local $/ = ""; 
            while (my $rec = <$h>) {
                my %e; my $k;
                for (split /\n/, $rec) { next if /^#/;
                    if (/^(id|file|from|to|test|why|equivalent):\s?(.*)$/) { $k = $1; $e{$k} = $2; }
                    elsif (defined $k) { $e{$k} .= "\n$_"; } }
                next unless $e{id};
                $n++;
                my $t = do { local $/; open my $s, "<", $e{file} or do { print "$f: $e{id}: no file $e{file}\n"; $bad++; next }; <$s> };
                my $c = () = $t =~ /\Q$e{from}\E/g;
                if ($c != 1) { print "$f: $e{id}: \"from\" occurs $c times in $e{file}\n"; $bad++; }
                if (!$e{test} && !$e{equivalent}) { print "$f: $e{id}: neither test nor equivalent\n"; $bad++; }
            } }
        print "mutate --check: $n mutants, ", ($bad ? "$bad stale" : "all apply"), "\n";
        exit($bad ? 1 : 0);'
    exit $?
fi
B=${MUTATE_DIR:-build-mutate}
T=$B/tree
mkdir -p "$T" || exit 2
# the copy: only files whose bytes changed are copied, so the build stays incremental
while IFS= read -r f; do
    if ! cmp -s "$f" "$T/$f"; then mkdir -p "$T/$(dirname "$f")" && cp -p "$f" "$T/$f"; fi
done < <(find CMakeLists.txt cmake include src tests tools fuzz bench assets docs/examples examples -type f 2>/dev/null)
# the test data (data/, filled by scripts/fetch-data.sh) is shared, not copied
scripts/fetch-data.sh >/dev/null 2>&1 || echo "mutate: warning: scripts/fetch-data.sh failed" >&2
ln -sfn "$root/data" "$T/data"
cmake -S "$T" -B "$B/build" -DCMAKE_BUILD_TYPE=RelWithDebInfo -DLUMIS_BUILD_BENCH=OFF >/dev/null || exit 2
B=$B/build
cache=$(cd "$B" && pwd)/test-cache
cmake --build "$B" -j"$(nproc)" >/dev/null || { echo "mutate: the unmutated build fails" >&2; exit 2; }
mods=("$@")
[ ${#mods[@]} -eq 0 ] && mods=($(ls tests/mutants/*.txt | xargs -n1 basename | sed 's/\.txt$//'))
backup=$(mktemp)
restore() { [ -n "${cur:-}" ] && cp "$backup" "$cur"; cur=; }
# A mutant of the output guard (src/io/atomic.c: never rename over a device) lets a test that
# writes to /dev/null, run as root, replace it with a regular file; the test catches the
# mutant, but the machine is left without /dev/null.  Put it back after every mutant.
devices() {
    local d
    for d in null:3 full:7; do
        [ -c /dev/${d%%:*} ] && continue
        echo "mutate: /dev/${d%%:*} was replaced (by mutant $id); restoring it" >&2
        rm -f /dev/${d%%:*} && mknod -m 666 /dev/${d%%:*} c 1 ${d##*:} 2>/dev/null || true
    done
}
trap 'restore; rm -f "$backup"' EXIT INT TERM
total_caught=0 total_scored=0 survived=0
summary=""
for mod in "${mods[@]}"; do
    f=tests/mutants/$mod.txt
    [ -f "$f" ] || { echo "mutate: no $f" >&2; exit 2; }
    caught=0 scored=0 equiv=0
    # entries: blank-line separated "key: value" lines (perl splits them; one record a line,
    # fields joined by \x1f, so that values keep their spaces)
    while IFS=$'\x1f' read -r id file from to test why equivalent; do
        [ -z "$id" ] && continue
        [ -n "${MUTATE_ONLY:-}" ] && [ "$id" != "$MUTATE_ONLY" ] && continue
        if [ -n "$equivalent" ]; then
            equiv=$((equiv + 1))
            printf '  %-8s %-36s equivalent: %s\n' "$mod" "$id" "$equivalent"
            continue
        fi
        scored=$((scored + 1))
        file=$T/$file
        cur=$file
        cp "$file" "$backup"
        n=$(FROM="$from" TO="$to" perl -0777 -e '
            my $t = do { local $/; open my $h, "<", $ARGV[0] or die; <$h> };
            my $n = () = $t =~ /\Q$ENV{FROM}\E/g;
            if ($n == 1) { my $i = index($t, $ENV{FROM});
                substr($t, $i, length $ENV{FROM}) = $ENV{TO};
                open my $o, ">", $ARGV[0] or die; print $o $t; }
            print $n;' "$file")
        if [ "$n" != 1 ]; then
            restore
            printf '  %-8s %-36s ERROR: "from" occurs %s times in %s\n' "$mod" "$id" "$n" "$file"
            survived=$((survived + 1))
            continue
        fi
        if ! cmake --build "$B" --target "$test" -j"$(nproc)" >/dev/null 2>&1; then
            result="caught (does not compile)"
            caught=$((caught + 1))
        elif (cd "$B/tests" && XDG_CACHE_HOME="$cache" timeout 600 "./$test" >/dev/null 2>&1); then
            result="SURVIVED ($why)"
            survived=$((survived + 1))
        else
            result="caught by $test"
            caught=$((caught + 1))
        fi
        restore
        devices
        printf '  %-8s %-36s %s\n' "$mod" "$id" "$result"
    done < <(perl -00 -ne '
        my %e; my $k;
        for (split /\n/) { next if /^#/;
            if (/^(id|file|from|to|test|why|equivalent):\s?(.*)$/) { $k = $1; $e{$k} = $2; }
            elsif (defined $k) { $e{$k} .= "\n$_"; } }
        print join("\x1f", map { $e{$_} // "" } qw(id file from to test why equivalent)), "\n"
            if $e{id};' "$f")
    summary+=$(printf '%-10s %d of %d caught (%d equivalent)\n' "$mod" "$caught" "$scored" "$equiv")$'\n'
    total_caught=$((total_caught + caught))
    total_scored=$((total_scored + scored))
done
# the sources as they were, and the build with them
cmake --build "$B" -j"$(nproc)" >/dev/null 2>&1
echo "mutate: per module"
printf '%s' "$summary"
echo "mutate: $total_caught of $total_scored non-equivalent mutants caught"
[ "$survived" -eq 0 ]
