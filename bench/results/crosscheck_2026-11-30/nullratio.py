import random, math
rng=random.Random(1)
N=20
for R in (2,3,4,5,10,20):
    mis=0; low=0; trials=20000; t2=[]
    for _ in range(trials):
        blocks=[[rng.gauss(0,1) for _ in range(N)] for _ in range(R)]
        allv=[v for b in blocks for v in b]; n=len(allv); m=sum(allv)/n
        s=math.sqrt(sum((v-m)**2 for v in allv)/(n-1)); se=s/math.sqrt(n)
        tot=sum(allv); loo=[(tot-sum(b))/(n-len(b)) for b in blocks]; lb=sum(loo)/R
        sej=math.sqrt((R-1)/R*sum((x-lb)**2 for x in loo))
        r=sej/se; mis+= (r>2 or r<0.5); low+= r<0.5
        t2.append((m/sej)**2)
    t2.sort()
    print(R, 'P(flag)=%.3f'%(mis/trials), 'P(<0.5)=%.3f'%(low/trials), 'median z^2 %.2f'%t2[len(t2)//2], 'expected', (R-1)/(R-3) if R>3 else 'inf')
