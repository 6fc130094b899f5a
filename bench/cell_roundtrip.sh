#!/bin/sh
# Request/reply round trip through a real cell-sim on 127.0.0.1:22001 (STA and OVR),
# p50/p99 over 20000 requests, against a baseline in the same run: a trivial C TCP
# echo server answering each 5-byte line with a 50-byte line (same sizes, no codec).
# "No regression": cell-sim's robot STA p50 at most 1.1x the echo server's in the same run
# (the 1.0 tree measured 111 against 112 us, 0.99x; the margin is the scheduler's noise).
set -eu
build=$1
dir=$build/bench
mkdir -p "$dir"
src=$dir/cell_rt.c
cat >"$src" <<'C'
#include <arpa/inet.h>
#include <netinet/in.h>
#include <netinet/tcp.h>
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/socket.h>
#include <time.h>
#include <unistd.h>
static unsigned long long now(void){struct timespec t;clock_gettime(CLOCK_MONOTONIC,&t);return t.tv_sec*1000000000ULL+t.tv_nsec;}
static int cmp(const void*a,const void*b){unsigned long long x=*(const unsigned long long*)a,y=*(const unsigned long long*)b;return (x>y)-(x<y);}
static int readline(int fd,char*b,int cap){int n=0;while(n<cap){int r=(int)recv(fd,b+n,1,0);if(r<=0)return -1;if(b[n++]=='\n')return n;}return -1;}
int main(int argc,char**argv){
  int port=atoi(argv[2]),one=1;struct sockaddr_in a;memset(&a,0,sizeof a);a.sin_family=AF_INET;a.sin_port=htons((unsigned short)port);inet_pton(AF_INET,"127.0.0.1",&a.sin_addr);
  if(strcmp(argv[1],"echo")==0){ /* baseline server: read a line, answer 50 bytes */
    int l=socket(AF_INET,SOCK_STREAM,0);setsockopt(l,SOL_SOCKET,SO_REUSEADDR,&one,sizeof one);
    if(bind(l,(struct sockaddr*)&a,sizeof a)||listen(l,4))return 3;
    for(;;){int c=accept(l,0,0);char b[64];setsockopt(c,IPPROTO_TCP,TCP_NODELAY,&one,sizeof one);
      while(readline(c,b,64)>0){if(send(c,"OKF+010.000-002.000+005.999-01.2322T+00080+00000\r\n",50,0)!=50)break;}close(c);}
  }
  int n=atoi(argv[3]);const char*req=argv[4];size_t rl=strlen(req);char line[64];memcpy(line,req,rl);line[rl]='\r';line[rl+1]='\n';
  int s=socket(AF_INET,SOCK_STREAM,0);if(connect(s,(struct sockaddr*)&a,sizeof a))return 3;setsockopt(s,IPPROTO_TCP,TCP_NODELAY,&one,sizeof one);
  unsigned long long*t=malloc(sizeof*t*(size_t)n);char b[64];
  for(int i=0;i<n+1000;i++){unsigned long long t0=now();if(send(s,line,rl+2,0)!=(ssize_t)(rl+2)||readline(s,b,64)<4)return 4;if(i>=1000)t[i-1000]=now()-t0;}
  qsort(t,(size_t)n,sizeof*t,cmp);
  printf("%-38s %8.1f %8.1f %8.1f\n",argv[5],t[n/2]/1000.0,t[(size_t)n*99/100]/1000.0,t[n-1]/1000.0);return 0;}
C
${CC:-cc} -std=c99 -D_POSIX_C_SOURCE=200809L -D_DEFAULT_SOURCE -O2 -o "$dir/cell_rt" "$src"
pids=''
cleanup() { for p in $pids; do kill "$p" 2>/dev/null || true; done; }
trap cleanup EXIT INT TERM
"$build/bin/cell-sim" -q -p 22001 >/dev/null 2>&1 & pids="$pids $!"
"$dir/cell_rt" echo 22009 & pids="$pids $!"
i=0
while ! python3 -c "import socket; socket.create_connection(('127.0.0.1',22001),0.2); socket.create_connection(('127.0.0.1',22009),0.2)" 2>/dev/null; do
  i=$((i + 1)); [ $i -gt 50 ] && { echo "cell_roundtrip: servers did not start" >&2; exit 1; }; sleep 0.1
done
N=20000
printf "%-38s %8s %8s %8s\n" "round trip, 127.0.0.1, $N requests" "p50 us" "p99 us" "max us"
"$dir/cell_rt" client 22009 $N STA "baseline: C echo server (5 B -> 50 B)" | tee "$dir/cell_rt.echo"
"$dir/cell_rt" client 22001 $N STA "cell-sim robot STA (5 B -> 50 B)" | tee "$dir/cell_rt.sta"
"$dir/cell_rt" client 22002 $N STA "cell-sim platform STA (5 B -> 34 B)"
"$dir/cell_rt" client 22001 $N OVR+00050 "cell-sim robot OVR (11 B -> 4 B)"
e=$(awk '{ print $(NF-2) }' "$dir/cell_rt.echo"); c=$(awk '{ print $(NF-2) }' "$dir/cell_rt.sta")
awk -v e="$e" -v c="$c" 'BEGIN { printf "cell_roundtrip: robot STA p50 %.1f us against the echo server %.1f us: %.2fx, no regression (<= 1.1x) %s\n",
  c, e, c / e, (c <= 1.1 * e ? "met" : "NOT") }'
