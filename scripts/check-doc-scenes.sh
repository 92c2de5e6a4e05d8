#!/usr/bin/env bash
# Renders every scene-file example of the documentation, so that none goes stale.
#
#   scripts/check-doc-scenes.sh [LUMIS]      (LUMIS: the lumis binary, default build/lumis)
#
# An example is a fenced code block of README.md or docs/**/*.md (or an indented block
# that starts with '{') holding a JSON object with "camera" or "objects": a scene file
# (docs/render.md, "Scene files").  Each is written to a folder of its own and rendered
# with `lumis render FILE.json --size 32x24 --spp 1 -o OUT.exr`.  Files an example names
# (meshes, maps, luminaire manifests) resolve against the scene's folder, so they are
# linked in beside it from the repository: the doc's folder, the repository's root,
# assets/, data/, data/meshes/, data/hdri/ (data/ is filled by scripts/fetch-data.sh).
# A luminaire manifest found nowhere is made with `lumis luminaire create --preset small`.
# Procedural maps (sky, studio[:WxH]) and presets (preset:car) need nothing.  An example
# naming a file that is nowhere is skipped, and said so.  A fenced json block that names
# "camera" or "objects" but is not valid JSON fails: a reader would refuse it too.
# Exit status: 0 when every example renders, 1 otherwise, 2 on a usage error.
set -uo pipefail

ROOT="$(cd "$(dirname "$0")/.." && pwd)"
LUMIS="${1:-$ROOT/build/lumis}"
case "$LUMIS" in /*) ;; *) LUMIS="$PWD/$LUMIS" ;; esac
if [ ! -x "$LUMIS" ]; then
    echo "usage: $0 [path/to/lumis]  ($LUMIS is not an executable)" >&2
    exit 2
fi
TMP="$(mktemp -d "${TMPDIR:-/tmp}/lumis-doc-scenes.XXXXXX")"
trap 'rm -rf "$TMP"' EXIT
cd "$ROOT" || exit 2

# Extract: one file per example, $TMP/NNN/scene.json, plus $TMP/NNN/origin (doc:line) and
# $TMP/NNN/files (one line per file the example names: key<TAB>value).
perl -MJSON::PP -e '
use strict; use warnings;
my ($tmp, @docs) = @ARGV;
my $n = 0; my $bad = 0;
sub walk_files {
    my ($j, $out) = @_;
    if (ref $j->{environment} eq "HASH" && defined $j->{environment}{map}) {
        push @$out, "map\t$j->{environment}{map}";
    }
    for my $o (@{ ref $j->{objects} eq "ARRAY" ? $j->{objects} : [] }) {
        push @$out, "mesh\t$o->{file}" if ref $o eq "HASH" && defined $o->{file};
    }
    for my $l (@{ ref $j->{luminaires} eq "ARRAY" ? $j->{luminaires} : [] }) {
        push @$out, "luminaire\t$l->{file}" if ref $l eq "HASH" && defined $l->{file};
    }
}
for my $doc (@docs) {
    open my $fh, "<:encoding(UTF-8)", $doc or die "$doc: $!";
    my @lines = <$fh>;
    close $fh;
    my $i = 0;
    while ($i < @lines) {
        my ($text, $start, $lang, $fenced);
        if ($lines[$i] =~ /^(\s*)(```+|~~~+)\s*([\w+-]*)/) {
            my ($ind, $fence) = ($1, $2);
            ($lang, $start, $fenced) = (lc($3 // ""), $i + 1, 1);
            my @body;
            $i++;
            while ($i < @lines && $lines[$i] !~ /^\s*\Q$fence\E\s*$/) { push @body, $lines[$i]; $i++; }
            $i++;
            $text = join "", @body;
        } elsif ($lines[$i] =~ /^    \s*\{/ && ($i == 0 || $lines[$i - 1] =~ /^\s*$/)) {
            ($lang, $start, $fenced) = ("", $i + 1, 0);
            my @body;
            while ($i < @lines && ($lines[$i] =~ /^    / || ($lines[$i] =~ /^\s*$/ && $i + 1 < @lines && $lines[$i + 1] =~ /^    /))) {
                push @body, $lines[$i]; $i++;
            }
            $text = join "", @body;
        } else { $i++; next; }
        next unless $text =~ /"(camera|objects)"\s*:/;
        next unless $lang eq "" || $lang eq "json" || $lang eq "jsonc" || $lang eq "json5";
        my $j = eval { JSON::PP->new->utf8(0)->decode($text) };
        if (!defined $j) {
            next unless $fenced && $lang eq "json"; # prose-like snippets in indented blocks
            (my $err = $@) =~ s/ at -e line.*//s;
            print STDERR "FAIL $doc:$start: a scene example that is not valid JSON: $err\n";
            $bad++;
            next;
        }
        next unless ref $j eq "HASH" && (exists $j->{camera} || exists $j->{objects});
        $n++;
        my $dir = sprintf "%s/%03d", $tmp, $n;
        mkdir $dir or die "$dir: $!";
        open my $o, ">:encoding(UTF-8)", "$dir/scene.json" or die; print $o $text; close $o;
        open $o, ">", "$dir/origin" or die; print $o "$doc:$start\n"; close $o;
        my @files; walk_files($j, \@files);
        open $o, ">:encoding(UTF-8)", "$dir/files" or die; print $o map { "$_\n" } @files; close $o;
    }
}
exit($bad ? 1 : 0);
' "$TMP" README.md $(find docs -name '*.md' | sort)
extract_rc=$?

failed=$extract_rc rendered=0 skipped=0
for dir in "$TMP"/[0-9]*; do
    [ -d "$dir" ] || continue
    origin="$(cat "$dir/origin")"
    docdir="$(dirname "${origin%:*}")"
    skip=""
    made=""
    while IFS=$'\t' read -r kind value; do
        [ -n "$kind" ] || continue
        case "$kind:$value" in
        map:sky | map:studio | map:sky:* | map:studio:* | luminaire:preset:*) continue ;;
        esac
        if [ "${value#/}" != "$value" ]; then # an absolute path: as it is
            [ -e "$value" ] || skip="names $value, which does not exist"
            continue
        fi
        found=""
        for base in "$docdir" . assets data data/meshes data/hdri; do
            for cand in "$base/$value" "$base/$(basename "$value")"; do
                if [ -f "$cand" ]; then found="$cand"; break 2; fi
            done
        done
        target="$dir/$value"
        case "$(realpath -m "$target")" in "$dir"/*) ;; *)
            skip="names $value, outside its own folder"
            continue ;;
        esac
        mkdir -p "$(dirname "$target")"
        if [ -n "$found" ]; then
            ln -sf "$ROOT/$found" "$target"
        elif [ "$kind" = luminaire ] && [ "${value%.json}" != "$value" ]; then
            if "$LUMIS" luminaire create "$target" --preset small >"$dir/create.log" 2>&1; then
                made="$made $value (lumis luminaire create --preset small)"
            else
                skip="names the luminaire $value, and creating one failed: $(tail -n 1 "$dir/create.log")"
            fi
        else
            skip="names $value, which is nowhere in the repository"
            case "$value" in *data/* | *.exr | *.hdr | *.pfm | *bunny.obj | *suzi.glb)
                [ -d data ] || skip="$skip (data/ is missing: scripts/fetch-data.sh)" ;;
            esac
        fi
    done <"$dir/files"
    if [ -n "$skip" ]; then
        echo "skip $origin: $skip"
        skipped=$((skipped + 1))
        continue
    fi
    if "$LUMIS" render "$dir/scene.json" --size 32x24 --spp 1 -o "$dir/out.exr" --quiet \
        >"$dir/render.log" 2>&1; then
        echo "ok   $origin${made:+ (made:$made)}"
        rendered=$((rendered + 1))
    else
        echo "FAIL $origin: lumis render refused it:"
        sed 's/^/       /' "$dir/render.log"
        failed=1
    fi
done
echo "scene examples: $rendered rendered, $skipped skipped$([ "$failed" = 0 ] || echo ", FAILURES above")"
[ "$rendered" -gt 0 ] || { echo "no scene example found in the documentation" >&2; failed=1; }
exit "$failed"
