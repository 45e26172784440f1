import re,sys
for sc in ['rtiow-final','three-spheres']:
  for f in ['waves','regenerate','regenerate+tail']:
    try: t=open(f'coh-{sc}-{f}.txt').read()
    except: continue
    rows=re.findall(r"from iteration (\d+)\s+(\d+)\s+([\d.]+)\s+([\d.]+)\s+([\d.]+)",t)
    if not rows: print(sc,f,'pending'); continue
    s=sum(int(r[1]) for r in rows)
    L=sum(int(r[1])*float(r[3]) for r in rows)/s; P=sum(int(r[1])*float(r[4]) for r in rows)/s
    late=[r for r in rows if int(r[0])>=8]; sl=sum(int(r[1]) for r in late)
    Ll=sum(int(r[1])*float(r[3]) for r in late)/sl if sl else 0
    it=re.search(r"^intersect\s+([\d.]+)\s+(\d+)",t,re.M)
    fr=re.search(r"([\d.]+) s frame",t)
    print(f"{sc:14} {f:16} subgroups {s:8} lines/subgroup {L:.2f} (iterations>=8: {Ll:.2f}, {sl} subgroups) pixel-spread {P:6.1f} intersect {float(it.group(1))/1e3:7.1f} s frame {fr.group(1)} s")
