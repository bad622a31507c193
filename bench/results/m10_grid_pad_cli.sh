#!/bin/bash
# the CLI hash check of docs/bench/grid.md "Padded strides"; MAIN = main's lanecast (a3daaf0)
# the generated raw volumes, written into /tmp/s10g/cli when missing:
mkdir -p /tmp/s10g/cli; cd /tmp/s10g/cli
[ -f w300f32.raw ] || python3 - <<'PY'
import math, array
def gen(name, nx, ny, nz, typ):
    a = array.array({'u16': 'H', 'i16': 'h', 'f32': 'f'}[typ])
    for k in range(nz):
        for j in range(ny):
            for i in range(nx):
                x, y, z = i / (nx - 1), j / (ny - 1), k / (nz - 1)
                f = math.exp(-((x-.4)**2 + (y-.5)**2 + (z-.5)**2) / 0.03) + 0.5 * math.exp(-((x-.7)**2 + (y-.4)**2 + (z-.6)**2) / 0.01)
                f = min(f, 1.0) * (0.75 + 0.25 * math.sin(9 * x) * math.cos(7 * y))
                a.append(int(f * 60000) if typ == 'u16' else int(f * 60000) - 30000 if typ == 'i16' else f)
    a.tofile(open(name + '.raw', 'wb'))
gen('w600u16', 600, 40, 30, 'u16'); gen('w1024u16', 1024, 48, 24, 'u16')
gen('w700i16', 700, 30, 20, 'i16'); gen('w300f32', 300, 40, 30, 'f32')
PY
# CLI renders, main vs new, hash with the TIFF date masked
NEW=/work/wt-s10-gpad/build/tools/lanecast; MAIN=/tmp/s10_main_lanecast; D=/work/shared/data/volumes
cd /tmp/s10g/cli; mkdir -p out
declare -A ISO=([engine]=150 [neghip]=100 [headsq]=1000 [hydrogen]=0.1 [embryo]=100 [HeadMRVolume]=100 [w600u16]=30000 [w1024u16]=30000 [w700i16]=0 [w300f32]=0.4)
inputs() {
  for v in engine neghip headsq hydrogen embryo; do echo "$v|$D/$v.nhdr|"; done
  echo "HeadMRVolume|$D/HeadMRVolume.mhd|"
  echo "w600u16|w600u16.raw|--dims 600,40,30 --type uint16 --spacing 1,15,20 --fov 14"
  echo "w1024u16|w1024u16.raw|--dims 1024,48,24 --type uint16 --spacing 1,21,42 --fov 14"
  echo "w700i16|w700i16.raw|--dims 700,30,20 --type int16 --spacing 1,23,35 --fov 14"
  echo "w300f32|w300f32.raw|--dims 300,40,30 --type float32 --spacing 1,7.5,10 --fov 14"
}
same=0; diff=0
while IFS='|' read name f extra; do
 for t in scalar avx2 avx512; do
  for m in "none" "phong" "mip" "iso" "brute"; do
   case $m in
    none) a="";; phong) a="--shade phong";; mip) a="--mode mip";; iso) a="--mode iso --iso ${ISO[$name]} --shade phong";; brute) a="--method brute --shade diffuse";;
   esac
   for B in MAIN NEW; do
    bin=${!B}
    $bin render $f $extra -o out/${name}_${t}_${m}_$B.tiff --size 203x157 --target $t --threads 2 $a 2>out/err_${name}_${t}_${m}_$B.txt || echo "ERR $B $name $t $m"
   done
   h1=$(perl -0777 -pe 's/\d{4}:\d\d:\d\d \d\d:\d\d:\d\d/DATE/g' out/${name}_${t}_${m}_MAIN.tiff | md5sum | cut -c1-32)
   h2=$(perl -0777 -pe 's/\d{4}:\d\d:\d\d \d\d:\d\d:\d\d/DATE/g' out/${name}_${t}_${m}_NEW.tiff | md5sum | cut -c1-32)
   if [ "$h1" = "$h2" ]; then same=$((same+1)); echo "same $name $t $m $h1"; else diff=$((diff+1)); echo "DIFF $name $t $m $h1 $h2"; fi
  done
 done
done < <(inputs)
echo "identical $same, different $diff"
