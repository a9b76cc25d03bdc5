-- | Persistent external engines (conformance/README.md, "Persistent
-- engines"): one process answers many requests, one JSON request a line on
-- its standard input, one JSON answer a line on its standard output.
--
-- A 'Pool' holds the engine processes that are idle; a case takes one (or
-- starts one), sends its request, reads one line of answer within the time
-- limit, and gives the process back. A process that misbehaves on a case (it
-- exits, is killed, takes too long, writes too much) is killed with its
-- whole process group and the case is an engine error; the next case starts
-- a fresh process, so a crash or a hang stays the error of its case. With
-- @-j N@ at most N processes are alive, each serving one case at a time.
module Stref.Conformance.Persistent
  ( Pool
  , newPool
  , closePool
  , askPersistent
  , exitedWith
  , cannotStart
  ) where

import Control.Concurrent (MVar, forkIO, modifyMVar, modifyMVar_, newMVar, swapMVar)
import Control.Concurrent.Async (Async, async, cancel, mapConcurrently_, waitCatch)
import Control.Exception (SomeException, onException, try)
import Control.Monad (void)
import qualified Data.ByteString as BS
import qualified Data.ByteString.Char8 as BSC
import qualified Data.ByteString.Lazy as BL
import Data.IORef
import Data.Text (Text)
import qualified Data.Text as T
import qualified Data.Text.Encoding as TE
import qualified Data.Text.Encoding.Error as TE
import System.Exit (ExitCode (..))
import System.IO (Handle, hClose, hFlush)
import System.Process
import System.Timeout (timeout)

-- | The message of an engine that exited with a status (the runner
-- recognises 127 and 126 as an engine that cannot be started).
exitedWith :: Int -> Text
exitedWith n = "the engine exited with status " <> T.pack (show n)

-- | The beginning of the message of an engine process that could not be
-- created.
cannotStart :: Text
cannotStart = "cannot start the engine"

-- | One running engine process.
data Engine = Engine
  { eIn :: Handle
  , eOut :: Handle
  , eErr :: Handle
  , eProcess :: ProcessHandle
  , eBuffer :: IORef BS.ByteString -- ^ what was read of its output after the last answer line
  , eStderr :: IORef BS.ByteString -- ^ the last 'stderrKept' bytes it wrote on stderr since its last answer
  , eDrain :: Async ()
  }

-- | The idle engine processes of one command.
data Pool = Pool
  { pCommand :: String
  , pIdle :: MVar [Engine]
  }

newPool :: String -> IO Pool
newPool cmd = Pool cmd <$> newMVar []

-- | End every idle process: close its input (a persistent engine exits at
-- end of input), give it a moment, then kill its group.
closePool :: Pool -> IO ()
closePool pool = do
  engines <- swapMVar (pIdle pool) []
  flip mapConcurrently_ engines $ \e -> do
    closeQuietly (eIn e)
    _ <- timeout 2000000 (try (waitForProcess (eProcess e)) :: IO (Either SomeException ExitCode))
    kill e

stderrKept :: Int
stderrKept = 2000

-- | Ask one request of the pool's engine: @Right@ the answer line as
-- written (without its newline), @Left@ what went wrong (the process is then
-- gone). The request must be one line of JSON.
askPersistent :: Pool -> Double -> Int -> BL.ByteString -> IO (Either Text BS.ByteString)
askPersistent pool seconds limit request = do
  taken <- modifyMVar (pIdle pool) $ \case
    e : es -> pure (es, Just e)
    [] -> pure ([], Nothing)
  started <- maybe (start (pCommand pool)) (pure . Right) taken
  case started of
    Left err -> pure (Left err)
    Right e -> do
      (result, healthy) <- exchange e seconds limit request `onException` kill e
      if healthy then modifyMVar_ (pIdle pool) (pure . (e :)) else kill e
      pure result

start :: String -> IO (Either Text Engine)
start cmd = do
  created <- try (createProcess (shell cmd) {std_in = CreatePipe, std_out = CreatePipe, std_err = CreatePipe, create_group = True})
  case created of
    Left (e :: SomeException) -> pure (Left (cannotStart <> ": " <> T.pack (show e)))
    Right (Just hin, Just hout, Just herr, ph) -> do
      buffer <- newIORef BS.empty
      kept <- newIORef BS.empty
      drain <- async (keepStderr herr kept)
      pure (Right (Engine hin hout herr ph buffer kept drain))
    Right _ -> pure (Left (cannotStart <> ": no pipes"))
  where
    keepStderr h kept = do
      r <- try (BS.hGetSome h 65536) :: IO (Either SomeException BS.ByteString)
      case r of
        Right chunk | not (BS.null chunk) -> do
          modifyIORef' kept (\old -> let new = old <> chunk in BS.drop (BS.length new - stderrKept) new)
          keepStderr h kept
        _ -> pure ()

data LineRead = Line BS.ByteString | TooLong | EndOfOutput

-- | Write the request line, read one answer line. The pipes are blocking
-- descriptors, so the write and the read run in threads of their own and
-- only the waiting is bounded by the time limit; on any trouble the caller
-- kills the process group, which ends them.
exchange :: Engine -> Double -> Int -> BL.ByteString -> IO (Either Text BS.ByteString, Bool)
exchange e seconds limit request = do
  writer <- async (BL.hPut (eIn e) (request <> "\n") >> hFlush (eIn e))
  reader <- async (readLine e limit)
  outcome <- timeout (max 1 (round (seconds * 1000000))) (waitCatch reader)
  let abandon = void (forkIO (cancel reader >> cancel writer))
  case outcome of
    Nothing -> kill e >> abandon >> pure (Left ("no answer within " <> T.pack (show seconds) <> " s"), False)
    Just (Left ex) -> kill e >> abandon >> pure (Left ("talking to the engine failed: " <> T.pack (show ex)), False)
    Just (Right TooLong) -> kill e >> abandon >> pure (Left ("the answer exceeds " <> T.pack (show limit) <> " bytes"), False)
    Just (Right (Line l)) -> do
      -- the engine answered, so it has read the request: the write is done
      -- (a process that answers before reading it all is not kept)
      written <- timeout 1000000 (waitCatch writer)
      writeIORef (eStderr e) BS.empty
      -- more output than one line is not kept either: it would be taken
      -- for the answer to the next request
      leftover <- readIORef (eBuffer e)
      let wrote = maybe False (either (const False) (const True)) written
      pure (Right l, wrote && BSC.all (`elem` (" \t\r\n" :: String)) leftover)
    Just (Right EndOfOutput) -> do
      -- the engine closed its output: it ended, or is ending
      code <- timeout 2000000 (try (waitForProcess (eProcess e)) :: IO (Either SomeException ExitCode))
      _ <- timeout 500000 (waitCatch (eDrain e))
      err <- stderrNote . TE.decodeUtf8With TE.lenientDecode <$> readIORef (eStderr e)
      abandon
      pure . (,False) . Left $ case code of
        Just (Right (ExitFailure n))
          | n < 0 -> "the engine was killed by signal " <> T.pack (show (negate n)) <> err
          | otherwise -> exitedWith n <> err
        Just (Right ExitSuccess) -> "the engine exited without answering the request (a persistent engine answers every request line with one line, then waits for the next)" <> err
        _ -> "the engine closed its output without answering" <> err
  where
    stderrNote t = if T.null (T.strip t) then "" else "; stderr: " <> T.strip t

-- | The next non-blank line of the engine's output (a trailing CR
-- dropped), keeping what follows it for the next request.
readLine :: Engine -> Int -> IO LineRead
readLine e limit = readIORef (eBuffer e) >>= fresh
  where
    -- a line from the start of @buf@
    fresh buf = case BSC.elemIndex '\n' buf of
      Just i -> found (BS.take i buf) (BS.drop (i + 1) buf)
      Nothing -> more [buf] (BS.length buf)
    -- read on; @acc@ (reversed) holds no newline
    more acc n
      | n > limit = pure TooLong
      | otherwise = do
          chunk <- BS.hGetSome (eOut e) 65536
          if BS.null chunk
            then writeIORef (eBuffer e) (BS.concat (reverse acc)) >> pure EndOfOutput
            else case BSC.elemIndex '\n' chunk of
              Just i -> found (BS.concat (reverse (BS.take i chunk : acc))) (BS.drop (i + 1) chunk)
              Nothing -> more (chunk : acc) (n + BS.length chunk)
    found line rest
      | BS.length line > limit = pure TooLong
      | blank line = fresh rest
      | otherwise = do
          writeIORef (eBuffer e) rest
          pure (Line (if BSC.isSuffixOf "\r" line then BS.init line else line))
    blank = BSC.all (`elem` (" \t\r" :: String))

-- | Kill the engine's process group, then reap it and close its pipes in the
-- background (a read still blocked ends when the group is dead).
kill :: Engine -> IO ()
kill e = do
  pid <- getPid (eProcess e)
  case pid of
    Just p -> void (try (readProcessWithExitCode "/bin/sh" ["-c", "kill -9 -" ++ show p ++ " 2>/dev/null"] "") :: IO (Either SomeException (ExitCode, String, String)))
    Nothing -> pure ()
  void . forkIO $ do
    void (try (waitForProcess (eProcess e)) :: IO (Either SomeException ExitCode))
    cancel (eDrain e)
    mapM_ closeQuietly [eIn e, eOut e, eErr e]

closeQuietly :: Handle -> IO ()
closeQuietly h = void (try (hClose h) :: IO (Either SomeException ()))
