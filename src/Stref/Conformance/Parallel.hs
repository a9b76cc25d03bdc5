-- | Work spread over several cores: the corpus is loaded and run by a few
-- workers, each bound to its own capability.
module Stref.Conformance.Parallel
  ( inParallel
  ) where

import Control.Concurrent.Async (asyncOn, cancel, wait)
import Control.Concurrent.MVar (newEmptyMVar, putMVar, readMVar)
import Control.Exception (bracket)
import Control.Monad (when)
import Data.IORef (atomicModifyIORef', newIORef)
import qualified Data.Vector as V

-- | @f@ on each element by @n@ workers, each taking the next element when it
-- is free; the results in the order of the elements. Each worker is bound to
-- a capability in turn: threads sharing one capability would wait for the
-- running one to yield, and an evaluation that does not allocate never
-- yields, so the cases would run one after the other.
inParallel :: Int -> (a -> IO b) -> [a] -> IO [b]
inParallel n f xs = do
  let items = V.fromList xs
  next <- newIORef (0 :: Int)
  slots <- V.replicateM (V.length items) newEmptyMVar
  let worker = do
        k <- atomicModifyIORef' next (\k -> (k + 1, k))
        when (k < V.length items) $ do
          f (items V.! k) >>= putMVar (slots V.! k)
          worker
  bracket (mapM (`asyncOn` worker) [0 .. n - 1]) (mapM_ cancel) (mapM_ wait)
  mapM readMVar (V.toList slots)
