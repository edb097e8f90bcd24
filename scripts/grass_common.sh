# Shared by the GRASS comparison scripts (sourced, not run): the terracast binary ($tc), a work folder removed on
# exit ($work), the DEM ($dem: the first argument, or the White Mountains SRTM tile warped to UTM 19N at
# $default_res metres, 90 unless the script sets it),
# a GRASS location holding it as raster `dem`, `g` to run a GRASS command quietly in that location, and
# `seconds` to time a command. Arguments: [DEM] [TERRACAST].
set -eu
here=$(cd "$(dirname "$0")/.." && pwd)
tc=${2:-$here/build/terracast}
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
if [ $# -ge 1 ]; then
    dem=$1
else
    res=${default_res:-90}
    dem=$work/white-mountains-utm19n-${res}m.tif
    gdalwarp -q -t_srs EPSG:32619 -tr "$res" "$res" -r bilinear "$here/data-samples/N44W072.srtm3-white-mountains-nh.hgt" "$dem"
fi
grass -c "$dem" "$work/gdb/loc" -e >/dev/null 2>&1
g() { grass "$work/gdb/loc/PERMANENT" --exec "$@" >/dev/null 2>&1; }
g r.in.gdal input="$dem" output=dem --quiet
seconds() { /usr/bin/time -f %e "$@" 2>&1 >/dev/null | tail -1; }
